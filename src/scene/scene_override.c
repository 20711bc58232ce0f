/* scene_override.c - scene overrides "KEY=VALUE" (brume render --set, brume_load_options.overrides):
 * a dotted path into the scene's JSON document set before the reader builds the scene.
 *
 * KEY is a path of object keys and array indices, "camera.fov", "media.0.sigma_s",
 * "media[0].density.seed", "stam.eps"; VALUE is read as one whole JSON value (5, [1, 2, 3],
 * true, "text"), and a bare word that is not JSON is taken as a string (stam.variant=paper);
 * text that starts as a number, array, object or quoted string must be whole ("1,024" is
 * refused, never read as its prefix 1). Missing objects on
 * the way are created, so "stam.eps=0.1" works on a scene without a "stam" object. The
 * document then goes through the one scene reader: every key and value is validated there,
 * and an unknown key fails there with the keys known at that place. What the reader cannot
 * see (an index past the end of an array, a path through a number) fails here, naming the
 * keys or indices the document has at that place. */
#include "scene/scene_override.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "io/json.h"

#define OVERRIDE_KEY_MAX 256
#define OVERRIDE_DEPTH_MAX 32

/* The segments of KEY, in place: '.' and '[' ']' separate them. Returns the count, or -1. */
static int split_key(char *key, char **seg)
{
    int n = 0;
    char *p = key;
    while (*p) {
        if (n == OVERRIDE_DEPTH_MAX)
            return -1;
        seg[n++] = p;
        while (*p && *p != '.' && *p != '[' && *p != ']')
            p++;
        if (*p == ']') { /* "[0]" closes: a '.' or '[' or the end must follow */
            *p++ = '\0';
            if (*p == '.')
                p++;
            else if (*p && *p != '[')
                return -1;
        } else if (*p == '.' || *p == '[') {
            *p++ = '\0';
        }
        if (seg[n - 1][0] == '\0')
            return -1;
    }
    return n;
}

static bool is_index(const char *s, int *out)
{
    if (!*s || strlen(s) > 9)
        return false;
    for (const char *p = s; *p; p++)
        if (!isdigit((unsigned char)*p))
            return false;
    *out = atoi(s);
    return true;
}

/* "media[0].density" for messages, the reader's spelling of the same path. */
static void path_text(char *buf, size_t n, char *const *seg, int count, const cJSON *const *node)
{
    buf[0] = '\0';
    for (int i = 0; i < count; i++) {
        size_t len = strlen(buf);
        if (cJSON_IsArray(node[i]))
            snprintf(buf + len, n - len, "[%s]", seg[i]);
        else
            snprintf(buf + len, n - len, "%s%s", i ? "." : "", seg[i]);
    }
}

/* The keys an object of the document holds, for a message. */
static void key_list(const cJSON *obj, char *buf, size_t n)
{
    buf[0] = '\0';
    for (const cJSON *c = obj->child; c; c = c->next) {
        size_t len = strlen(buf);
        snprintf(buf + len, n - len, "%s%s", len ? ", " : "", c->string);
    }
}

static brume_status apply_one(cJSON *root, const char *source, const char *text)
{
    const char *eq = strchr(text, '=');
    if (!eq || eq == text || (size_t)(eq - text) >= OVERRIDE_KEY_MAX)
        return err_set(BRUME_ERROR_PARSE, "%s: override '%s': expected KEY=VALUE", source, text);
    char key[OVERRIDE_KEY_MAX], *seg[OVERRIDE_DEPTH_MAX];
    const cJSON *node[OVERRIDE_DEPTH_MAX];
    snprintf(key, sizeof key, "%.*s", (int)(eq - text), text);
    int n = split_key(key, seg);
    if (n <= 0)
        return err_set(BRUME_ERROR_PARSE, "%s: override '%s': bad key path (use a.b.0.c or a.b[0].c)", source, text);
    const char *vtext = eq + 1;
    cJSON *value = cJSON_ParseWithOpts(vtext, NULL, true); /* the whole text, not a prefix of it */
    if (value && json_bad_number(vtext)) { /* "01", "1.": what JSON refuses, cJSON takes */
        cJSON_Delete(value);
        value = NULL;
    }
    size_t lead = strspn(vtext, " \t\r\n");
    if (!value && vtext[lead] && strchr("-+.0123456789[{\"", vtext[lead]))
        return err_set(BRUME_ERROR_PARSE, "%s: override %.*s: '%s' is not one whole JSON value (a number, array, "
                       "object or quoted string; a bare word is a string)", source, (int)(eq - text), text, vtext);
    if (!value)
        value = cJSON_CreateString(vtext);
    if (!value)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", source);

    cJSON *cur = root;
    char where[512], keys[512];
    for (int i = 0; i < n; i++) {
        node[i] = cur;
        bool last = i == n - 1;
        int idx;
        if (cJSON_IsArray(cur)) {
            int size = cJSON_GetArraySize(cur);
            if (!is_index(seg[i], &idx) || idx >= size) {
                path_text(where, sizeof where, seg, i, node);
                cJSON_Delete(value);
                if (size == 0)
                    return err_set(BRUME_ERROR_PARSE, "%s: override %.*s: %s is an empty array", source,
                                   (int)(eq - text), text, where);
                return err_set(BRUME_ERROR_PARSE, "%s: override %.*s: %s has %d element%s: index 0 to %d", source,
                               (int)(eq - text), text, where, size, size == 1 ? "" : "s", size - 1);
            }
            if (last) {
                cJSON_ReplaceItemInArray(cur, idx, value);
                return BRUME_OK;
            }
            cur = cJSON_GetArrayItem(cur, idx);
        } else if (cJSON_IsObject(cur)) {
            cJSON *child = cJSON_GetObjectItemCaseSensitive(cur, seg[i]);
            if (last) {
                if (child)
                    cJSON_ReplaceItemInObjectCaseSensitive(cur, seg[i], value);
                else
                    cJSON_AddItemToObject(cur, seg[i], value); /* the reader says whether it may be here */
                return BRUME_OK;
            }
            if (!child) {
                /* a missing object on the way: "stam.eps" on a scene without "stam" */
                if (!(child = cJSON_AddObjectToObject(cur, seg[i]))) {
                    cJSON_Delete(value);
                    return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", source);
                }
            }
            cur = child;
        } else {
            /* a path through a number or a string: name the keys its parent holds */
            path_text(where, sizeof where, seg, i, node);
            key_list(node[i - 1], keys, sizeof keys); /* i > 0: the root is an object */
            cJSON_Delete(value);
            return err_set(BRUME_ERROR_PARSE, "%s: override %.*s: %s is a %s and has no key '%s' (the document has "
                           "here: %s)", source, (int)(eq - text), text, where,
                           cJSON_IsNumber(cur) ? "number" : cJSON_IsString(cur) ? "string" : "value", seg[i],
                           cJSON_IsArray(node[i - 1]) ? "array elements" : keys);
        }
    }
    cJSON_Delete(value); /* not reached: the loop returns at the last segment */
    return BRUME_OK;
}

brume_status scene_apply_overrides(cJSON *root, const char *source, const char *const *overrides, int n)
{
    if (n > 0 && !cJSON_IsObject(root))
        return err_set(BRUME_ERROR_PARSE, "%s: (top level): expected an object", source);
    for (int i = 0; i < n; i++) {
        if (!overrides[i])
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: override %d is NULL", source, i);
        brume_status st = apply_one(root, source, overrides[i]);
        if (st)
            return st;
    }
    return BRUME_OK;
}

void scene_override_annotate(const char *const *overrides, int n)
{
    /* The reader names the key it refused, "FILE: media[0].sigma_s: ..." or "FILE: stam.epz:
     * unknown key": when an override set that key, say so, since the file does not hold it. */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", err_message());
    for (int i = n - 1; i >= 0; i--) {
        const char *eq = overrides[i] ? strchr(overrides[i], '=') : NULL;
        if (!eq || (size_t)(eq - overrides[i]) >= OVERRIDE_KEY_MAX)
            continue;
        char key[OVERRIDE_KEY_MAX], norm[2 * OVERRIDE_KEY_MAX], *seg[OVERRIDE_DEPTH_MAX];
        snprintf(key, sizeof key, "%.*s", (int)(eq - overrides[i]), overrides[i]);
        int ns = split_key(key, seg);
        if (ns <= 0)
            continue;
        norm[0] = '\0';
        for (int k = 0; k < ns; k++) {
            size_t len = strlen(norm);
            int idx;
            if (is_index(seg[k], &idx))
                snprintf(norm + len, sizeof norm - len, "[%d]", idx);
            else
                snprintf(norm + len, sizeof norm - len, "%s%s", k ? "." : "", seg[k]);
        }
        /* the reader names the key or the first unknown object on the path: try each prefix */
        for (size_t len = strlen(norm); len > 0;) {
            char want[2 * OVERRIDE_KEY_MAX + 4];
            snprintf(want, sizeof want, ": %.*s:", (int)len, norm);
            if (strstr(msg, want)) {
                err_set(err_status(), "%.1000s (set by override %s)", msg, overrides[i]);
                return;
            }
            while (len > 0 && norm[len - 1] != '.' && norm[len - 1] != '[')
                len--;
            if (len > 0)
                len--; /* drop the separator */
        }
    }
}
