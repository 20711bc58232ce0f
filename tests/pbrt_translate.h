/* pbrt_translate.h - the pbrt tests' translation of a .pbrt text, written to the test's
 * temporary file NAME: its JSON scene, or NULL with *msg set to the refusal. */
#ifndef BRUME_TESTS_PBRT_TRANSLATE_H
#define BRUME_TESTS_PBRT_TRANSLATE_H

#include <stdio.h>
#include <stdlib.h>

#include <cjson/cJSON.h>

#include "core/error.h"
#include "scene/scene_pbrt.h"
#include "test.h"

static inline cJSON *pbrt_translate(const char *name, const char *text, char *msg, size_t cap)
{
    const char *path = test_tmp_path(name);
    test_write_file(path, text);
    char *json = NULL;
    msg[0] = '\0';
    if (scene_pbrt_json(path, &json) != BRUME_OK) {
        snprintf(msg, cap, "%s", err_message());
        return NULL;
    }
    cJSON *root = cJSON_Parse(json);
    free(json);
    ASSERT_TRUE(root != NULL);
    return root;
}

#endif
