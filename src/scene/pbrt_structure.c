/* pbrt_structure.c - the structure of a pbrt-v4 file as pbrt-v4's parser and scene builder
 * check it (src/pbrt/parser.cpp, scene.cpp): the block each directive belongs to (options
 * before WorldBegin, the scene description after it), AttributeBegin/End and ObjectBegin/End
 * in pairs, and a file that ends inside the world block with every block closed. pbrt-v4
 * warns about an unmatched AttributeEnd and ignores it; brume refuses it, as every other
 * violation, in one line at FILE:LINE. */
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "scene/pbrt.h"

typedef enum { BLOCK_OPTIONS, BLOCK_WORLD, BLOCK_ANY } pbrt_block;

/* Every directive of pbrt-v4 and its block (scene.cpp's VERIFY_OPTIONS and VERIFY_WORLD;
 * Import is checked by the parser; TransformBegin/End are AttributeBegin/End there). */
static const struct {
    const char *name;
    pbrt_block block;
} directives[] = {
    {"Accelerator", BLOCK_OPTIONS},   {"Camera", BLOCK_OPTIONS},          {"Film", BLOCK_OPTIONS},
    {"Integrator", BLOCK_OPTIONS},    {"PixelFilter", BLOCK_OPTIONS},     {"Sampler", BLOCK_OPTIONS},
    {"TransformTimes", BLOCK_OPTIONS}, {"WorldBegin", BLOCK_OPTIONS},

    {"AreaLightSource", BLOCK_WORLD}, {"AttributeBegin", BLOCK_WORLD},    {"AttributeEnd", BLOCK_WORLD},
    {"Import", BLOCK_WORLD},          {"LightSource", BLOCK_WORLD},       {"MakeNamedMaterial", BLOCK_WORLD},
    {"Material", BLOCK_WORLD},        {"NamedMaterial", BLOCK_WORLD},     {"ObjectBegin", BLOCK_WORLD},
    {"ObjectEnd", BLOCK_WORLD},       {"ObjectInstance", BLOCK_WORLD},    {"ReverseOrientation", BLOCK_WORLD},
    {"Shape", BLOCK_WORLD},           {"Texture", BLOCK_WORLD},           {"TransformBegin", BLOCK_WORLD},
    {"TransformEnd", BLOCK_WORLD},

    {"ActiveTransform", BLOCK_ANY},   {"Attribute", BLOCK_ANY},           {"ColorSpace", BLOCK_ANY},
    {"ConcatTransform", BLOCK_ANY},   {"CoordinateSystem", BLOCK_ANY},    {"CoordSysTransform", BLOCK_ANY},
    {"Identity", BLOCK_ANY},          {"Include", BLOCK_ANY},             {"LookAt", BLOCK_ANY},
    {"MakeNamedMedium", BLOCK_ANY},   {"MediumInterface", BLOCK_ANY},     {"Option", BLOCK_ANY},
    {"Rotate", BLOCK_ANY},            {"Scale", BLOCK_ANY},               {"Transform", BLOCK_ANY},
    {"Translate", BLOCK_ANY},
};

/* Refuses dir where pbrt-v4 would: not one of its directives, or outside its block. */
brume_status pbrt_structure_directive(pbrt_state *S, const char *dir)
{
    const lexer *L = &S->L;
    for (size_t i = 0; i < sizeof directives / sizeof directives[0]; i++) {
        if (strcmp(dir, directives[i].name) != 0)
            continue;
        if (directives[i].block == BLOCK_OPTIONS && S->world && strcmp(dir, "WorldBegin") == 0)
            return pbrt_fail(L, "WorldBegin given twice (first at line %d)", S->world_line);
        if (directives[i].block == BLOCK_OPTIONS && S->world)
            return pbrt_fail(L, "%s after WorldBegin (line %d): pbrt-v4 takes options before WorldBegin only", dir,
                             S->world_line);
        if (directives[i].block == BLOCK_WORLD && !S->world)
            return pbrt_fail(L, "%s before WorldBegin: pbrt-v4 takes the scene description after WorldBegin only",
                             dir);
        return BRUME_OK;
    }
    if (strcmp(dir, "WorldEnd") == 0)
        return pbrt_fail(L, "WorldEnd: a pbrt-v3 directive that pbrt-v4 does not have (`pbrt --upgrade` converts the "
                            "file)");
    return pbrt_fail(L, "unknown directive \"%.64s\" (not one of pbrt-v4's)", dir);
}

/* AttributeBegin (or pbrt-v4's alias TransformBegin): a copy of the current attributes. */
brume_status pbrt_attribute_begin(pbrt_state *S, const char *dir)
{
    if (S->depth + 1 == PBRT_MAX_DEPTH)
        return pbrt_fail(&S->L, "%s: nested more than %d deep", dir, PBRT_MAX_DEPTH - 1);
    S->a[S->depth + 1] = S->a[S->depth];
    S->depth++;
    S->a[S->depth].begin_line = S->L.dir_line;
    pbrt_next(&S->L);
    return BRUME_OK;
}

/* AttributeEnd (or TransformEnd): back to the attributes of the matching begin. */
brume_status pbrt_attribute_end(pbrt_state *S, const char *dir)
{
    if (S->depth == 0)
        return pbrt_fail(&S->L, "%s without an open AttributeBegin", dir);
    S->depth--;
    pbrt_next(&S->L);
    return BRUME_OK;
}

/* At the end of the file: inside the world block, every AttributeBegin closed. */
brume_status pbrt_structure_end(pbrt_state *S)
{
    const lexer *L = &S->L;
    if (!S->world) /* named at the last directive read */
        return err_set(BRUME_ERROR_PARSE, "%s:%d: the file ends before WorldBegin (truncated?)", L->file, L->dir_line);
    if (S->depth > 0)
        return err_set(BRUME_ERROR_PARSE, "%s:%d: AttributeBegin never closed: the file ends inside it (truncated?)",
                       L->file, S->a[S->depth].begin_line);
    return BRUME_OK;
}
