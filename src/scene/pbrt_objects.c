/* pbrt_objects.c - pbrt's object instancing: ObjectBegin "name" ... ObjectEnd records its
 * directives, ObjectInstance "name" reads them again where it stands, so that each instance
 * becomes shapes of its own (brume has no instances). */
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "scene/pbrt.h"

/* What an object may hold in brume: transforms, attributes, materials and drawn shapes.
 * Identity and Transform would drop the instance's transform, which the replay holds in
 * the current transform. */
static bool allowed_in_object(const char *dir)
{
    static const char *const ok[] = {"Translate", "Scale", "Rotate", "LookAt", "ConcatTransform", "AttributeBegin",
                                     "AttributeEnd", "Shape", "Material", "NamedMaterial", "MakeNamedMaterial"};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++)
        if (strcmp(dir, ok[i]) == 0)
            return true;
    return false;
}

/* ObjectBegin "name": the object recorded, its directives passed over to its ObjectEnd. */
static brume_status object_begin(pbrt_state *S)
{
    lexer *L = &S->L;
    pbrt_next(L);
    if (L->kind != TOK_STRING)
        return pbrt_fail(L, "ObjectBegin: expected its name");
    if (S->instancing)
        return pbrt_fail(L, "ObjectBegin inside an ObjectInstance");
    for (int i = 0; i < S->nobjs; i++)
        if (strcmp(S->objs[i].name, L->text) == 0)
            return pbrt_fail(L, "ObjectBegin \"%s\": an object of that name is already defined", L->text);
    if (S->nobjs == PBRT_MAX_OBJECTS)
        return pbrt_fail(L, "ObjectBegin: more than %d objects", PBRT_MAX_OBJECTS);
    pbrt_object *o = &S->objs[S->nobjs];
    pbrt_copy(o->name, sizeof o->name, L->text);
    o->a = S->a[S->depth];
    pbrt_next(L);
    o->at = *L;
    while (!(L->kind == TOK_WORD && strcmp(L->text, "ObjectEnd") == 0)) {
        if (L->kind == TOK_END || (L->kind == TOK_WORD && strcmp(L->text, "ObjectBegin") == 0))
            return pbrt_fail(L, "ObjectBegin \"%s\": no ObjectEnd before %s", o->name,
                             L->kind == TOK_END ? "the end of the file" : "the next ObjectBegin");
        pbrt_next(L);
    }
    pbrt_next(L);
    S->nobjs++;
    return BRUME_OK;
}

/* ObjectInstance "name": the object's directives read again from the graphics state it was
 * defined in, its transform now the instance's: pbrt-v4 places an instance's shapes by the
 * transform at ObjectInstance times their own, both from the world (the reader's world may
 * start from a mirror M, so the instance's transform is taken back through M^-1 = M). */
static brume_status object_instance(pbrt_state *S, params *ps, brume_status (*directive)(pbrt_state *, params *))
{
    lexer *L = &S->L;
    pbrt_next(L);
    if (L->kind != TOK_STRING)
        return pbrt_fail(L, "ObjectInstance: expected a name");
    if (S->instancing)
        return pbrt_fail(L, "ObjectInstance inside an object");
    if (S->depth + 1 == PBRT_MAX_DEPTH)
        return pbrt_fail(L, "ObjectInstance: nested too deep");
    const pbrt_object *o = NULL;
    for (int i = 0; i < S->nobjs && !o; i++)
        if (strcmp(S->objs[i].name, L->text) == 0)
            o = &S->objs[i];
    if (!o)
        return pbrt_fail(L, "ObjectInstance \"%s\": no ObjectBegin of that name before it", L->text);
    if (o->a.area)
        return pbrt_fail(L, "ObjectInstance \"%s\": an area light on an object (pbrt-v4 refuses it too)", o->name);
    pbrt_next(L);
    lexer outer = *L;
    int depth = S->depth;
    m4 inst = pbrt_m4_mul(S->a[depth].ctm, pbrt_world_origin(S));
    S->a[depth + 1] = o->a;
    S->a[depth + 1].ctm = pbrt_m4_mul(inst, o->a.ctm);
    S->depth++;
    S->instancing = true;
    *L = o->at;
    L->outer = NULL; /* the Include that read the object has returned */
    brume_status st = BRUME_OK;
    while (st == BRUME_OK && !(L->kind == TOK_WORD && strcmp(L->text, "ObjectEnd") == 0)) {
        const attrs *a = &S->a[S->depth];
        bool media = strcmp(L->text, "Shape") == 0 && (strcmp(a->material, "interface") == 0 || a->inside[0]);
        if (L->kind == TOK_WORD && (!allowed_in_object(L->text) || media)) {
            L->dir_line = L->tok_line;
            st = pbrt_unsupported(L, "%s inside ObjectBegin \"%s\": brume instances transforms, attributes, materials and "
                                     "drawn shapes%s", L->text, o->name, media ? " (not media)" : "");
        } else {
            st = directive(S, ps);
        }
    }
    if (st == BRUME_OK && S->depth != depth + 1)
        st = pbrt_fail(L, "ObjectBegin \"%s\": AttributeBegin and AttributeEnd do not balance", o->name);
    S->instancing = false;
    S->depth = depth;
    *L = outer;
    return st;
}

brume_status pbrt_object_directive(pbrt_state *S, params *ps, const char *dir,
                                   brume_status (*directive)(pbrt_state *, params *))
{
    if (strcmp(dir, "ObjectBegin") == 0)
        return object_begin(S);
    if (strcmp(dir, "ObjectInstance") == 0)
        return object_instance(S, ps, directive);
    if (strcmp(dir, "ObjectEnd") == 0)
        return pbrt_fail(&S->L, "ObjectEnd without an open ObjectBegin");
    return pbrt_unsupported(&S->L, "%s: not supported by brume's pbrt reader (docs/pbrt.md lists what is)", dir);
}
