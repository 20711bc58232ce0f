/* test_pbrt_conventions.c - pbrt-v4's conventions that the comparison with pbrt-v4's own
 * renders (bench/pbrt_scenes.sh on tests/pbrt_conventions/, docs/pbrt-scenes.md) showed brume
 * translating differently, each checked against a value worked out from pbrt-v4's
 * definition. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>

#include "brume.h"

#define VIEW "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"

/* pbrt-v4's DistantLight::Create: scale /= SpectrumToPhotometric(L) (for an rgb L the colour
 * space's illuminant, so rgb is read as written), then scale *= E_v for an "illuminance"
 * E_v > 0. rgb L (1, 2, 3), scale 2 and illuminance 5 give the irradiance (10, 20, 30). */
TEST(distant_illuminance_as_pbrt)
{
    char msg[2048];
    cJSON *root = pbrt_translate("distant.pbrt",
                                 "Film \"rgb\"\n" VIEW "WorldBegin\n"
                                 "LightSource \"distant\" \"rgb L\" [1 2 3] \"float scale\" [2]"
                                 " \"float illuminance\" [5]\n"
                                 "LightSource \"distant\" \"rgb L\" [1 2 3] \"float scale\" [2]\n",
                                 msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    const cJSON *E = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 0), "irradiance");
    const cJSON *E1 = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 1), "irradiance");
    for (int c = 0; c < 3; c++) {
        ASSERT_NEAR(cJSON_GetArrayItem(E, c)->valuedouble, (c + 1) * 2 * 5, 1e-9);
        ASSERT_NEAR(cJSON_GetArrayItem(E1, c)->valuedouble, (c + 1) * 2, 1e-9); /* none: the scale alone */
    }
    cJSON_Delete(root);
}

TEST_MAIN(distant_illuminance_as_pbrt)
