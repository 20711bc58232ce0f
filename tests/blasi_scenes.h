/* blasi_scenes.h - the scene the blasi tests render (test_blasi*.c): a fractal cloud of
 * 32 x 32 x 8 voxels with LIGHTS spliced in, and the sun that lights it. */
#ifndef BRUME_TEST_BLASI_SCENES_H
#define BRUME_TEST_BLASI_SCENES_H

/* A fractal cloud of 32 x 32 x 8 voxels read constant per voxel (the paper's model, and
 * what `single` sees too), chromatic scattering (so Eq. 10's average and the RGB weights
 * are exercised), isotropic phase: with r = 1 the stored radiance is exactly the
 * single-scattering source. Voxels are optically thin (tau <= 0.3), so the voxel
 * discretization bias is well under 1 %. LIGHTS is spliced in. CLOUD_SCENE_FILTER: the
 * same cloud with the grid's filter FILTER ("nearest", or "trilinear": what `single` sees
 * of it, and what blasi sees with blasi.interpolate = trilinear). */
#define CLOUD_SCENE(LIGHTS, EXTRA) CLOUD_SCENE_FILTER(LIGHTS, EXTRA, "nearest")
#define CLOUD_SCENE_FILTER(LIGHTS, EXTRA, FILTER)                                                                   \
    "{\"camera\": {\"position\": [0.6, -3.5, 3.0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 40},"       \
    " \"lights\": [" LIGHTS "],"                                                                                    \
    " \"media\": [{\"sigma_a\": [0.2, 0.1, 0.4], \"sigma_s\": [3, 1.5, 0.75],"                                      \
    "   \"density\": {\"type\": \"fractal_cloud\", \"dims\": [32, 32, 8], \"seed\": 3, \"threshold\": 0.1,"         \
    "     \"filter\": \"" FILTER "\","                                                                               \
    "     \"bounds\": [[-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]]}}],"                                                     \
    " \"render\": {\"width\": 40, \"height\": 40, \"spp\": 4, \"method\": \"blasi\"}" EXTRA "}"

#define SUN "{\"type\": \"distant\", \"direction\": [0.4, 0.3, -1], \"irradiance\": [2, 2.5, 3]}"

#endif
