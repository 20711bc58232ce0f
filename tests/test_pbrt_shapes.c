/* test_pbrt_shapes.c - pbrt-v4's disk and cylinder as brume's triangles (docs/pbrt.md): 2048
 * segments a turn with their corners on the exact surface, facing pbrt's normal, against
 * the shapes' areas and radii worked out by hand; a diffuse disk lit by a point light
 * above its centre against Lambert's law; and area lights emitting from pbrt's side. */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "io/json.h"
#include "scene/scene_pbrt.h"

#define HEAD                                                                                     \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [64]\n"                                         \
    "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [1]\n"      \
    "WorldBegin\n"

/* The one surface of HEAD + world, translated: its positions (3 nv) and indices (3 nt). */
static cJSON *surface(const char *world, cJSON **root)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEAD, world);
    const char *path = test_tmp_path("shape.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    *root = cJSON_Parse(json);
    free(json);
    remove(path);
    cJSON *surf = cJSON_GetObjectItemCaseSensitive(*root, "surfaces");
    ASSERT_EQ_INT(cJSON_GetArraySize(surf), 1);
    return cJSON_GetArrayItem(surf, 0);
}

/* The mesh's points and triangles: total area and the area-weighted normal. */
static void mesh_area(const cJSON *s, double *area, double n[3], double **P, int *nv)
{
    const cJSON *pos = cJSON_GetObjectItemCaseSensitive(s, "positions"), *idx = cJSON_GetObjectItemCaseSensitive(s, "indices");
    *nv = cJSON_GetArraySize(pos) / 3;
    *P = malloc((size_t)*nv * 3 * sizeof **P);
    ASSERT_TRUE(*P != NULL);
    int i = 0;
    for (const cJSON *e = pos->child; e; e = e->next)
        (*P)[i++] = e->valuedouble;
    *area = 0.0;
    n[0] = n[1] = n[2] = 0.0;
    int nt = cJSON_GetArraySize(idx) / 3;
    for (int t = 0; t < nt; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = &(*P)[3 * cJSON_GetArrayItem(idx, 3 * t + k)->valueint];
        double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        *area += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int k = 0; k < 3; k++)
            n[k] += 0.5 * c[k];
    }
}

/* A disk of radius 2 at height 0.5, moved by Translate 1 0 0: every point at z = 0.5 within 2
 * of (1, 0), the rim's on it; the inscribed 2048-gon's area (2048 / 2) r^2 sin(2 pi / 2048),
 * within 1.6e-6 of pi r^2, facing +z. An annulus (innerradius 1) and a half turn (phimax
 * 180) likewise. */
TEST(disk_is_its_polygon)
{
    const struct { const char *params; double area, rin; } c[] = {
        {"", 1024.0 * 4.0 * sin(2.0 * PI / 2048.0), 0.0},
        {" \"float innerradius\" 1", 1024.0 * 3.0 * sin(2.0 * PI / 2048.0), 1.0},
        {" \"float phimax\" 180", 512.0 * 4.0 * sin(2.0 * PI / 2048.0), 0.0}};
    for (int k = 0; k < 3; k++) {
        char world[512];
        snprintf(world, sizeof world, "Translate 1 0 0\nShape \"disk\" \"float radius\" 2 \"float height\" 0.5%s\n",
                 c[k].params);
        cJSON *root;
        const cJSON *s = surface(world, &root);
        double area, n[3], *P;
        int nv;
        mesh_area(s, &area, n, &P, &nv);
        ASSERT_NEAR(area, c[k].area, 1e-9 * c[k].area);
        ASSERT_NEAR(n[2], area, 1e-9 * area); /* every facet faces +z */
        for (int i = 0; i < nv; i++) {
            double rho = hypot(P[3 * i] - 1.0, P[3 * i + 1]);
            ASSERT_NEAR(P[3 * i + 2], 0.5, 1e-12);
            if (!(fabs(rho - 2.0) < 1e-12 || fabs(rho - c[k].rin) < 1e-12))
                TEST_FAIL("disk %d: point %d at %g from the axis", k, i, rho);
        }
        free(P);
        cJSON_Delete(root);
    }
}

/* A cylinder of radius 0.5 from z = -1 to 2: its 4096 facets' area 2048 r sin(pi / 2048) x 2
 * x 3 (within 4e-7 of 2 pi r h), facing out: the facets' outward area vectors of a closed
 * turn sum to 0; of a half turn to (0, 2 r h, 0), the chords' normals times their lengths
 * summing to the closing diameter's (r h (cos 0 - cos pi) along +y, by hand). Inward facets
 * would give -2 r h. */
TEST(cylinder_is_its_prism)
{
    cJSON *root;
    const cJSON *s = surface("Shape \"cylinder\" \"float radius\" 0.5 \"float zmin\" -1 \"float zmax\" 2\n", &root);
    double area, n[3], *P;
    int nv;
    mesh_area(s, &area, n, &P, &nv);
    ASSERT_NEAR(area, 2048.0 * 2.0 * 0.5 * sin(PI / 2048.0) * 3.0, 1e-9);
    ASSERT_NEAR(fabs(n[0]) + fabs(n[1]) + fabs(n[2]), 0.0, 1e-9);
    for (int i = 0; i < nv; i++)
        ASSERT_NEAR(hypot(P[3 * i], P[3 * i + 1]), 0.5, 1e-12);
    free(P);
    cJSON_Delete(root);
    s = surface("Shape \"cylinder\" \"float radius\" 0.5 \"float zmin\" -1 \"float zmax\" 2 \"float phimax\" 180\n", &root);
    mesh_area(s, &area, n, &P, &nv);
    ASSERT_NEAR(n[1], 2.0 * 0.5 * 3.0, 1e-9);
    ASSERT_NEAR(n[0], 0.0, 1e-9);
    free(P);
    cJSON_Delete(root);
}

/* A diffuse disk (reflectance 0.5, radius 10) seen straight on from 5 away through a
 * 1-degree view, lit by a point light of intensity 4 at 1 above its centre on the camera's
 * side: radiance 0.5 / pi x 4 / 1^2 at the centre; across the view (+-0.044 on the disk) the
 * irradiance falls by at most cos^3 = 1 - 0.0029. Tolerance: 4 standard errors plus that. */
TEST(disk_lit_by_lambert)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEAD,
             "LightSource \"point\" \"rgb I\" [4 4 4] \"point3 from\" [0 0 -1]\n"
             "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"disk\" \"float radius\" 10\n");
    const char *path = test_tmp_path("disk.pbrt");
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 19);
    int npix = brume_image_width(img) * brume_image_height(img);
    double want = 0.5 / PI * 4.0;
    for (int c = 0; c < 3; c++) {
        double mean, se;
        test_channel_mean(brume_image_pixels(img), npix, c, &mean, &se);
        if (!(fabs(mean - want * (1.0 - 0.0015)) <= 4.0 * se + 0.0015 * want))
            TEST_FAIL("channel %d: mean %.6f, want %.6f (se %g)", c, mean, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
}

/* The mean of channel c of the image of a pbrt file (16 x 16, 4 samples a pixel). */
static double render_mean(const char *text, int c)
{
    const char *path = test_tmp_path("area.pbrt");
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 23);
    double mean, se;
    test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), c, &mean, &se);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
    return mean;
}

/* AreaLightSource "diffuse": a patch filling the 1-degree view emits L scale = (1, 2, 3) x 2
 * toward the camera from the side pbrt's normal faces, (p10 - p00) x (p01 - p00) = -z here,
 * toward the camera at z = -5: each pixel is that radiance, with pbrt's right-handed view
 * (Scale -1 1 1) and with its bare LookAt, which brume translates as a mirrored world (the
 * mirror reverses the triangles, which the reader turns back). The patch turned around emits
 * nothing toward the camera, unless twosided; an iso of 200 doubles it. */
TEST(area_light_faces_pbrt_normal)
{
    const char *views[2] = {"Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n", "LookAt 0 0 -5  0 0 0  0 1 0\n"};
    const char *patch[2] = {"[-9 -9 0  -9 9 0  9 -9 0  9 9 0]", "[-9 -9 0  9 -9 0  -9 9 0  9 9 0]"};
    for (int v = 0; v < 2; v++)
        for (int back = 0; back < 2; back++)
            for (int two = 0; two < 2; two++) {
                char text[2048];
                snprintf(text, sizeof text,
                         "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"float iso\" 200\n"
                         "Sampler \"halton\" \"integer pixelsamples\" 4\n%sCamera \"perspective\" \"float fov\" 1\n"
                         "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3] \"float scale\" 2%s\n"
                         "Material \"diffuse\" \"rgb reflectance\" [0 0 0]\nShape \"bilinearmesh\" \"point3 P\" %s\n"
                         "AttributeEnd\n", views[v], two ? " \"bool twosided\" true" : "", patch[back]);
                double want = back && !two ? 0.0 : 2.0 * 2.0 * 3.0;
                double got = render_mean(text, 2);
                if (!(fabs(got - want) <= 1e-5 * 12.0))
                    TEST_FAIL("view %d, patch %s, twosided %d: blue %g, want %g", v, back ? "turned" : "facing", two,
                              got, want);
            }
}

/* What would emit from a side brume cannot tell, or with a power brume cannot spread as
 * pbrt-v4 does, each refused by name. */
TEST(area_light_refusals)
{
    const char *cases[][2] = {
        {"Shape \"plymesh\" \"string filename\" ", "a one-sided area light from a PLY mesh with vertex normals"},
        {"AreaLightSource \"diffuse\" \"float power\" 10\n"
         "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 0 2 0] \"integer indices\" [0 1 2 0 2 3]\n",
         "an area light's \"power\" on a shape whose triangles differ in area"},
        {"Material \"interface\"\nShape \"sphere\"\n", "an area light on an \"interface\" shape"},
        {"AreaLightSource \"goniometric\"\n", "AreaLightSource \"goniometric\""}};
    test_write_file(test_tmp_path("tri.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                              "property float y\nproperty float z\nproperty float nx\n"
                                              "property float ny\nproperty float nz\nelement face 1\n"
                                              "property list uchar int vertex_indices\nend_header\n"
                                              "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
    for (int i = 0; i < 4; i++) {
        char world[1024], text[4096];
        snprintf(world, sizeof world, "%s", cases[i][0]);
        if (i == 0) /* the file's name, quoted */
            snprintf(world + strlen(world), sizeof world - strlen(world), "\"%s\"\n", test_tmp_path("tri.ply"));
        snprintf(text, sizeof text, "%sAreaLightSource \"diffuse\"\n%s", HEAD, world);
        const char *path = test_tmp_path("bad.pbrt");
        test_write_file(path, text);
        char *json = NULL;
        ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
        ASSERT_CONTAINS(err_message(), cases[i][1]);
        remove(path);
    }
    remove(test_tmp_path("tri.ply"));
}

/* MakeNamedMaterial keeps a material by name (a later one of the name replaces it) and sets
 * nothing; NamedMaterial makes it current; an unknown name is refused. */
TEST(named_materials_as_pbrt)
{
    cJSON *root;
    const cJSON *s = surface("MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.5 0.1 0.1]\n"
                             "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.6 0.2 0.1]\n"
                             "Material \"diffuse\" \"rgb reflectance\" [0.3 0.3 0.3]\nNamedMaterial \"red\"\n"
                             "Shape \"sphere\"\n", &root);
    const cJSON *albedo = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(s, "material"), "albedo");
    ASSERT_NEAR(cJSON_GetArrayItem(albedo, 0)->valuedouble, 0.6, 1e-12);
    ASSERT_NEAR(cJSON_GetArrayItem(albedo, 1)->valuedouble, 0.2, 1e-12);
    cJSON_Delete(root);
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEAD, "NamedMaterial \"blue\"\n");
    const char *path = test_tmp_path("named.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
    ASSERT_CONTAINS(err_message(), ":7: NamedMaterial \"blue\": no MakeNamedMaterial of that name");
    remove(path);
}

/* The translation of text, or NULL with the message in err_message(). */
static cJSON *translate_text(const char *text)
{
    const char *path = test_tmp_path("obj.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    brume_status st = scene_pbrt_json(path, &json);
    remove(path);
    if (st != BRUME_OK)
        return NULL;
    cJSON *root = cJSON_Parse(json);
    free(json);
    return root;
}

/* ObjectBegin/ObjectInstance: each instance is the object's shapes placed by the transform
 * at ObjectInstance times their own (pbrt-v4), here Translate 5 0 0 (then none) times
 * Translate 0 0 1: a triangle's first corner (0, 0, 0) lands at (5, 0, 1) and (0, 0, 1); in
 * the world a bare LookAt mirrors (x -> -x), at (-5, 0, 1). The object's own material is the
 * one at ObjectBegin. A light inside an object, an unknown name and a stray ObjectEnd are
 * refused by name. */
TEST(object_instances_as_pbrt)
{
    const char *views[2] = {"Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n", "LookAt 0 0 -5  0 0 0  0 1 0\n"};
    for (int v = 0; v < 2; v++) {
        char text[4096];
        snprintf(text, sizeof text,
                 "%sCamera \"perspective\"\nWorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n"
                 "ObjectBegin \"tri\"\nTranslate 0 0 1\n"
                 "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\nObjectEnd\n"
                 "Material \"diffuse\" \"rgb reflectance\" [0.9 0.9 0.9]\n"
                 "AttributeBegin\nTranslate 5 0 0\nObjectInstance \"tri\"\nAttributeEnd\nObjectInstance \"tri\"\n",
                 views[v]);
        cJSON *root = translate_text(text);
        if (!root)
            TEST_FAIL("%s", err_message());
        const cJSON *surf = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
        ASSERT_EQ_INT(cJSON_GetArraySize(surf), 2);
        for (int i = 0; i < 2; i++) {
            const cJSON *sp = cJSON_GetArrayItem(surf, i);
            const cJSON *P = cJSON_GetObjectItemCaseSensitive(sp, "positions");
            double x = (i == 0 ? 5.0 : 0.0) * (v == 1 ? -1.0 : 1.0);
            ASSERT_NEAR(cJSON_GetArrayItem(P, 0)->valuedouble, x, 1e-12);
            ASSERT_NEAR(cJSON_GetArrayItem(P, 2)->valuedouble, 1.0, 1e-12);
            const cJSON *alb = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(sp, "material"), "albedo");
            ASSERT_NEAR(cJSON_GetArrayItem(alb, 2)->valuedouble, 0.3, 1e-12);
        }
        cJSON_Delete(root);
    }
    const char *bad[][2] = {
        {"ObjectBegin \"o\"\nLightSource \"point\"\nObjectEnd\nObjectInstance \"o\"\n",
         ":8: LightSource inside ObjectBegin \"o\""},
        {"ObjectInstance \"p\"\n", ":7: ObjectInstance \"p\": no ObjectBegin of that name"},
        {"ObjectEnd\n", ":7: ObjectEnd without an open ObjectBegin"},
        {"ObjectBegin \"o\"\nShape \"sphere\"\n", "no ObjectEnd before the end of the file"}};
    for (int i = 0; i < 4; i++) {
        char text[4096];
        snprintf(text, sizeof text, "%s%s", HEAD, bad[i][0]);
        ASSERT_TRUE(translate_text(text) == NULL);
        ASSERT_CONTAINS(err_message(), bad[i][1]);
    }
}

/* A disk or cylinder bounds no volume: as an interface shape it is refused. */
TEST(open_shapes_bound_no_medium)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEAD, "Material \"interface\"\nShape \"disk\"\n");
    const char *path = test_tmp_path("open.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
    char want[1200];
    snprintf(want, sizeof want, "%s:8: Shape \"disk\": an \"interface\" shape that bounds no volume", path);
    ASSERT_CONTAINS(err_message(), want);
    remove(path);
}

TEST_MAIN(disk_is_its_polygon, cylinder_is_its_prism, disk_lit_by_lambert, open_shapes_bound_no_medium,
          area_light_faces_pbrt_normal, area_light_refusals, named_materials_as_pbrt, object_instances_as_pbrt)
