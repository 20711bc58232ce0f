/* test_options.c - the methods' option tables (method/method_options.h) drive everything
 * that names an option: the setter (ranges, kinds, messages, side effects), the defaults,
 * the scene reader's method objects and --set, include/brume.h's list of keys, the tool's
 * help (`brume help render`, `brume options`) and docs/scene-format.md's "Method options". A
 * test here fails when any of them drifts from the tables. */
#define _GNU_SOURCE /* open_memstream */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "commands.h"
#include "core/error.h"
#include "method/blasi_options.h"
#include "method/method_options.h"
#include "method/path_options.h"
#include "method/stam_params.h"
#include "test.h"

#define SCENE_HEAD "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}"

/* A struct of def's options with its defaults, in an over-aligned buffer. */
typedef struct opts_buf {
    _Alignas(16) unsigned char b[sizeof(blasi_options) + sizeof(stam_params) + sizeof(path_options)];
} opts_buf;

static void fresh(const method_options_def *def, opts_buf *o)
{
    ASSERT_TRUE(def->size <= sizeof o->b);
    memset(o, 0, sizeof *o); /* the bytes past def->size too: set() compares the whole buffer */
    method_options_default(def, o->b);
}

/* Sets key from text; on failure the struct must be left as it was. */
static brume_status set(const method_options_def *def, opts_buf *o, const char *key, const char *text)
{
    opts_buf before = *o;
    brume_status st = method_option_set(def, o->b, key, text);
    if (st != BRUME_OK && memcmp(&before, o, sizeof before) != 0)
        TEST_FAIL("%s = '%s' failed (%s) but changed the options", key, text, err_message());
    return st;
}

static void accept(const method_options_def *def, opts_buf *o, const char *key, const char *text)
{
    if (set(def, o, key, text) != BRUME_OK)
        TEST_FAIL("%s = '%s' refused: %s", key, text, err_message());
}

static void refuse(const method_options_def *def, opts_buf *o, const char *key, const char *text, brume_status want)
{
    brume_status st = set(def, o, key, text);
    if (st != want)
        TEST_FAIL("%s = '%s': status %d, want %d (%s)", key, text, (int)st, (int)want, err_message());
    ASSERT_CONTAINS(err_message(), key);
    ASSERT_TRUE(strchr(err_message(), '\n') == NULL);
}

/* The field of row r as a number (enum and bool as their index). */
static double field(const method_option *r, const opts_buf *o)
{
    const void *f = o->b + r->offset;
    switch (r->store) {
    case OPTION_STORE_DOUBLE:
        return *(const double *)f;
    case OPTION_STORE_INT:
        return *(const int *)f;
    case OPTION_STORE_UINT:
        return *(const unsigned *)f;
    case OPTION_STORE_U64:
        return (double)*(const uint64_t *)f;
    case OPTION_STORE_BOOL:
        return *(const bool *)f;
    default:
        TEST_FAIL("%s: not a number field", r->key);
    }
    return 0.0;
}

static const char *num(double v, char *buf)
{
    sprintf(buf, "%.17g", v);
    return buf;
}

/* Every row of every table: its default parses, its range's ends are taken and stored, what
 * lies just outside is refused with the key in the message and nothing changed. */
TEST(setter_follows_the_table)
{
    for (int m = 0; m < METHOD_OPTIONS_COUNT; m++) {
        const method_options_def *def = method_options_def_get((method_options_id)m);
        ASSERT_TRUE(def->count > 0);
        for (int i = 0; i < def->count; i++) {
            const method_option *r = &def->options[i];
            opts_buf o;
            char a[64];
            fresh(def, &o);
            ASSERT_TRUE(strncmp(r->key, def->method, strlen(def->method)) == 0 && r->key[strlen(def->method)] == '.');
            ASSERT_TRUE(r->what && r->what[0] && r->doc && r->doc[0] && !strchr(r->doc, '\n'));
            ASSERT_TRUE(r->offset + r->size <= def->size);
            if (r->def)
                accept(def, &o, r->key, r->def);
            if (r->kind != OPTION_PATH)
                refuse(def, &o, r->key, "x",
                       r->kind == OPTION_ENUM || r->kind == OPTION_BOOL ? BRUME_ERROR_PARSE : BRUME_ERROR_RANGE);
            switch (r->kind) {
            case OPTION_NUMBER:
            case OPTION_INTEGER:
                ASSERT_TRUE(r->lo < r->hi);
                accept(def, &o, r->key, num(r->lo, a));
                ASSERT_EQ_INT(field(r, &o) == r->lo, 1);
                if (r->flags & OPTION_HI_OPEN) {
                    refuse(def, &o, r->key, num(r->hi, a), BRUME_ERROR_RANGE);
                } else {
                    accept(def, &o, r->key, num(r->hi, a));
                    ASSERT_EQ_INT(field(r, &o) == r->hi, 1);
                }
                refuse(def, &o, r->key, num(r->hi < 1e300 ? nextafter(r->hi, INFINITY) * (r->hi >= 1.0 ? 2.0 : 1.0)
                                                          : INFINITY, a),
                       BRUME_ERROR_RANGE);
                refuse(def, &o, r->key, num(r->lo - (r->kind == OPTION_INTEGER ? 1.0 : fmax(1e-300, fabs(r->lo))), a),
                       BRUME_ERROR_RANGE);
                refuse(def, &o, r->key, "nan", BRUME_ERROR_RANGE);
                refuse(def, &o, r->key, "", BRUME_ERROR_RANGE);
                if (r->kind == OPTION_INTEGER)
                    refuse(def, &o, r->key, num(r->lo + 0.5, a), BRUME_ERROR_RANGE);
                if (r->flags & OPTION_ZERO_OR) {
                    accept(def, &o, r->key, "0");
                    ASSERT_EQ_INT(field(r, &o) == 0.0, 1);
                }
                break;
            case OPTION_ENUM:
                for (int k = 0; r->names[k]; k++) {
                    accept(def, &o, r->key, r->names[k]);
                    if (r->store != OPTION_STORE_NONE)
                        ASSERT_EQ_INT(field(r, &o), k);
                }
                break;
            case OPTION_BOOL:
                accept(def, &o, r->key, "false");
                ASSERT_EQ_INT(field(r, &o), 0);
                accept(def, &o, r->key, "true");
                ASSERT_EQ_INT(field(r, &o), 1);
                refuse(def, &o, r->key, "yes", BRUME_ERROR_PARSE);
                break;
            case OPTION_COLOR:
                accept(def, &o, r->key, "0.5");
                accept(def, &o, r->key, "1,2,3");
                ASSERT_EQ_INT(((const color *)(o.b + r->offset))->c[2] == 3.0, 1);
                refuse(def, &o, r->key, "1,2", BRUME_ERROR_RANGE);
                refuse(def, &o, r->key, "1,2,3,4", BRUME_ERROR_RANGE);
                refuse(def, &o, r->key, "-1", BRUME_ERROR_RANGE);
                break;
            case OPTION_PATH: {
                ASSERT_EQ_INT(r->store, OPTION_STORE_CHARS);
                accept(def, &o, r->key, "a/b.light");
                ASSERT_EQ_STR((const char *)(o.b + r->offset), "a/b.light");
                char *big = malloc(r->size + 1);
                memset(big, 'a', r->size);
                big[r->size] = '\0';
                refuse(def, &o, r->key, big, BRUME_ERROR_RANGE);
                big[r->size - 1] = '\0';
                accept(def, &o, r->key, big);
                free(big);
                break;
            }
            }
        }
        ASSERT_TRUE(strstr(method_options_methods(), def->method) != NULL); /* the methods messages name */
        opts_buf o;
        fresh(def, &o);
        char unknown[64];
        snprintf(unknown, sizeof unknown, "%s.no_such_key", def->method);
        refuse(def, &o, unknown, "1", BRUME_ERROR_PARSE);
        ASSERT_CONTAINS(err_message(), "unknown key (known here: ");
    }
}

/* A bound in `what`: "1e12", "2^53", "-1". */
static double bound(const char *s)
{
    if (strncmp(s, "2^", 2) == 0)
        return ldexp(1.0, atoi(s + 2));
    return strtod(s, NULL);
}

/* The words of a row (`what`, as messages, help and docs say it) state its range: "in
 * [a, b]" / "(a, b)" / "[a, b)", ">= a", "> a", "0 or ..." / "(0 = ...)" with OPTION_ZERO_OR,
 * else no bound at all. */
TEST(range_words_match_the_range)
{
    for (int m = 0; m < METHOD_OPTIONS_COUNT; m++) {
        const method_options_def *def = method_options_def_get((method_options_id)m);
        for (int i = 0; i < def->count; i++) {
            const method_option *r = &def->options[i];
            if (r->kind != OPTION_NUMBER && r->kind != OPTION_INTEGER && r->kind != OPTION_COLOR)
                continue;
            const char *w = r->what;
            const char *in = strstr(w, " in [") ? strstr(w, " in [") : strstr(w, " in (");
            bool zero = strncmp(w, "0 or ", 5) == 0 || strncmp(w, "0 (", 3) == 0 || strstr(w, "(0 = off)");
            ASSERT_EQ_INT(zero, (r->flags & OPTION_ZERO_OR) != 0);
            if (in) {
                char open = in[4];
                const char *comma = strchr(in, ',');
                const char *close = comma + strcspn(comma, "])");
                double lo = bound(in + 5), hi = bound(comma + 2);
                if (open == '[')
                    ASSERT_EQ_INT(r->lo == lo, 1);
                else
                    ASSERT_TRUE(r->lo > lo && r->lo < lo + 1e-5);
                if (*close == ']') {
                    ASSERT_EQ_INT(r->hi == hi, 1);
                    ASSERT_EQ_INT(r->flags & OPTION_HI_OPEN, 0);
                } else {
                    ASSERT_TRUE((r->hi == hi && (r->flags & OPTION_HI_OPEN)) || (r->hi < hi && r->hi > hi - 1e-5));
                }
            } else if (strstr(w, ">= ")) {
                ASSERT_EQ_INT(r->lo == bound(strstr(w, ">= ") + 3), 1);
                ASSERT_TRUE(r->hi >= OPTION_BIG);
            } else if (strstr(w, "> ")) {
                double lo = bound(strstr(w, "> ") + 2);
                ASSERT_TRUE(r->lo > lo && r->lo <= lo + 1e-9);
                ASSERT_TRUE(r->hi >= OPTION_BIG);
            } else {
                if (!(r->lo <= -OPTION_BIG && r->hi >= OPTION_BIG))
                    TEST_FAIL("%s: '%s' states no range but the row has [%g, %g]", r->key, r->what, r->lo, r->hi);
            }
        }
    }
}

/* The defaults the methods had before their tables (path_options_default, blasi_options_default
 * and stam_params_default, by hand): the same values, bit for bit. */
TEST(defaults_are_unchanged)
{
    path_options p;
    method_options_default(&path_options_def, &p);
    ASSERT_EQ_INT(p.sun_lobe == 2.0 && p.sun_roulette == 0.03 && p.split == 1.0, 1);
    blasi_options b;
    method_options_default(&blasi_options_def, &b);
    ASSERT_EQ_INT(b.light_rays, 1u << 21);
    ASSERT_TRUE(isnan(b.r) && isnan(b.kprime));
    ASSERT_EQ_INT(b.step == 0.0 && b.threshold == 1e-3, 1);
    ASSERT_EQ_INT(b.sources, 16);
    ASSERT_EQ_INT(b.exit_deposit, BLASI_EXIT_PAPER);
    ASSERT_EQ_INT(b.view_attenuation, BLASI_VIEW_ABSORPTION);
    ASSERT_EQ_INT(b.gather, BLASI_GATHER_PATH_LENGTH);
    ASSERT_EQ_INT(b.voxels, 0);
    ASSERT_EQ_INT(b.save_light[0] == '\0' && b.load_light[0] == '\0', 1);
    ASSERT_EQ_INT(b.exit_given || b.view_given, 0);
    stam_params s;
    method_options_default(&stam_options_def, &s);
    ASSERT_EQ_INT(s.eps == 0.0 && s.eta == 1e30 && s.alpha == 0.05 && s.cell == 0.0, 1);
    ASSERT_EQ_INT(s.lattice, 0);
    ASSERT_EQ_INT(s.seed, 1);
    ASSERT_EQ_INT(s.time == 0.0 && s.rate == 1.0, 1);
    ASSERT_EQ_INT(s.ambient.c[0] == 0.0 && s.ambient.c[1] == 0.0 && s.ambient.c[2] == 0.0, 1);
    ASSERT_EQ_INT(s.steps, 16);
    ASSERT_EQ_INT(s.light_grid, 32);
    ASSERT_EQ_INT(s.bvh && !s.paper && s.voxelize_realization, 1);
    ASSERT_EQ_INT(s.voxelize_resolution, 0);
}

/* blasi.variant sets exit_deposit and view_attenuation, except one given by its own key,
 * before or after it. */
TEST(blasi_variant_leaves_keys_given)
{
    opts_buf o;
    const blasi_options *b = (const blasi_options *)o.b;
    fresh(&blasi_options_def, &o);
    accept(&blasi_options_def, &o, "blasi.variant", "physical");
    ASSERT_EQ_INT(b->exit_deposit == BLASI_EXIT_NONE && b->view_attenuation == BLASI_VIEW_EXTINCTION, 1);
    accept(&blasi_options_def, &o, "blasi.variant", "paper");
    ASSERT_EQ_INT(b->exit_deposit == BLASI_EXIT_PAPER && b->view_attenuation == BLASI_VIEW_ABSORPTION, 1);
    fresh(&blasi_options_def, &o);
    accept(&blasi_options_def, &o, "blasi.view_attenuation", "absorption");
    accept(&blasi_options_def, &o, "blasi.variant", "physical");
    ASSERT_EQ_INT(b->exit_deposit == BLASI_EXIT_NONE && b->view_attenuation == BLASI_VIEW_ABSORPTION, 1);
    fresh(&blasi_options_def, &o);
    accept(&blasi_options_def, &o, "blasi.variant", "physical");
    accept(&blasi_options_def, &o, "blasi.exit_deposit", "paper");
    accept(&blasi_options_def, &o, "blasi.variant", "physical");
    ASSERT_EQ_INT(b->exit_deposit == BLASI_EXIT_PAPER && b->view_attenuation == BLASI_VIEW_EXTINCTION, 1);
}

/* Messages as the hand-written setters wrote them (tests and users match on them). */
TEST(messages_are_unchanged)
{
    static const char *const cases[][3] = {
        {"path.split", "9", "path.split: '9' is not a whole number in [1, 8]"},
        {"path.sun_lobe", "-0.5", "path.sun_lobe: '-0.5' is not a number in [0, 100]"},
        {"path.clamp", "1", "path.clamp: unknown key (known here: sun_lobe, sun_roulette, split)"},
        {"blasi.kprime", "1", "blasi.kprime: '1' is not a number in (-1, 1)"},
        {"blasi.threshold", "1", "blasi.threshold: '1' is not a number in [0, 1)"},
        {"blasi.step", "-1", "blasi.step: '-1' is not a length >= 0 (0 = voxel by voxel)"},
        {"blasi.light_rays", "1.5", "blasi.light_rays: '1.5' is not an integer in [1, 1e12]"},
        {"blasi.voxels", "1", "blasi.voxels: '1' is not 0 or an integer in [2, 2048]"},
        {"blasi.exit_deposit", "sometimes", "blasi.exit_deposit: 'sometimes' is not one of paper, none"},
        {"blasi.gather", "x", "blasi.gather: 'x' is not one of path_length, printed"},
        {"blasi.rays", "2", "blasi.rays: unknown key (known here: light_rays, r, kprime, step, threshold, sources, "
                            "exit_deposit, view_attenuation, gather, interpolate, variant, voxels, save_light, load_light)"},
        {"stam.lattice", "1", "stam.lattice: '1' is not 0 (automatic) or an integer in [2, 512]"},
        {"stam.voxelize.resolution", "1", "stam.voxelize.resolution: '1' is not an integer in [2, 2048] (0 = off)"},
        {"stam.ambient", "1,2", "stam.ambient: '1,2' is not a radiance >= 0 (v or r,g,b)"},
        {"stam.steps", "0", "stam.steps: '0' is not an integer in [1, 256]"},
        {"stam.seed", "-1", "stam.seed: '-1' is not an integer in [0, 2^53]"},
        {"stam.time", "inf", "stam.time: 'inf' is not a finite time in seconds"},
        {"stam.bvh", "yes", "stam.bvh: 'yes' is not true or false"},
        /* the one message that changed: it was "unknown variant 'x' (known: paper, corrected)" */
        {"stam.variant", "x", "stam.variant: 'x' is not one of corrected, paper"},
        {"stam.epz", "0.1", "stam.epz: unknown key (known here: eps, eta, alpha, lattice, cell, seed, time, rate, "
                            "ambient, steps, light_grid, bvh, variant, kernel, kernel_file, overlap, voxelize.resolution, "
                            "voxelize.realization)"},
    };
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_new(ctx, "opts", &s), BRUME_OK);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ASSERT_TRUE(brume_scene_set_option(ctx, s, cases[i][0], cases[i][1]) != BRUME_OK);
        char want[1024];
        snprintf(want, sizeof want, "opts: %s", cases[i][2]);
        ASSERT_EQ_STR(brume_context_last_error(ctx), want);
    }
    char big[1100];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.save_light", big), BRUME_ERROR_RANGE);
    ASSERT_EQ_STR(brume_context_last_error(ctx), "opts: blasi.save_light: path longer than 1023 bytes");
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* ---- the places that list the options --------------------------------------------------- */

/* The text between the line holding `begin` and the line holding `end` (excluded), malloc'd. */
static char *between(const char *text, const char *begin, const char *end, const char *where)
{
    const char *a = strstr(text, begin);
    if (!a)
        TEST_FAIL("%s: no line with '%s'", where, begin);
    a = strchr(a, '\n') + 1;
    const char *b = strstr(a, end);
    if (!b)
        TEST_FAIL("%s: no line with '%s' after '%s'", where, end, begin);
    while (b > a && b[-1] != '\n')
        b--;
    char *out = malloc((size_t)(b - a) + 1);
    memcpy(out, a, (size_t)(b - a));
    out[b - a] = '\0';
    return out;
}

/* Fails with the first line where got and want differ, and the whole of want. */
static void same_text(const char *got, const char *want, const char *what, const char *how)
{
    if (strcmp(got, want) == 0)
        return;
    int line = 1;
    const char *g = got, *w = want;
    while (*g && *g == *w) {
        if (*g == '\n')
            line++;
        g++;
        w++;
    }
    while (g > got && g[-1] != '\n')
        g--, w--;
    fprintf(stderr, "%s differs from the option tables at its line %d:\n  has:    %.*s\n  tables: %.*s\n"
                    "%s; the text the tables give:\n%s",
            what, line, (int)strcspn(g, "\n"), g, (int)strcspn(w, "\n"), w, how, want);
    TEST_FAIL("%s drifted from the option tables", what);
}

static char *source_file(const char *rel)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", BRUME_SOURCE_DIR, rel);
    size_t n;
    return test_slurp(path, &n);
}

/* include/brume.h's list of keys (at brume_scene_set_option) is the tables'. */
TEST(header_lists_every_key)
{
    char *h = source_file("include/brume.h");
    char *got = between(h, " * BEGIN OPTION KEYS", " * END OPTION KEYS", "include/brume.h");
    char *want = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&want, &n);
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        ASSERT_EQ_INT(brume_option_get(NULL, i, &o), BRUME_OK);
        fprintf(f, " *   %-26s %s\n", o.key, o.values);
    }
    fclose(f);
    same_text(got, want, "include/brume.h's list of option keys", "paste it between BEGIN and END OPTION KEYS");
    free(want);
    free(got);
    free(h);
}

/* docs/scene-format.md's "Method options" tables are `brume options --markdown`'s. */
TEST(doc_is_generated)
{
    char *doc = source_file("docs/scene-format.md");
    char *got = between(doc, "<!-- BEGIN brume options --markdown -->", "<!-- END brume options --markdown -->",
                        "docs/scene-format.md");
    char *want = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&want, &n);
    fputc('\n', f);
    cli_options_markdown(f);
    fputc('\n', f);
    fclose(f);
    same_text(got, want, "docs/scene-format.md's \"Method options\"",
              "scripts/option-docs.sh rewrites it (`brume options --markdown` between BEGIN and END)");
    free(want);
    free(got);
    free(doc);
}

/* true when key stands in text as a whole word (not inside a longer key) */
static bool has_key(const char *text, const char *key)
{
    size_t n = strlen(key);
    for (const char *p = strstr(text, key); p; p = strstr(p + 1, key)) {
        bool before = p == text || !(p[-1] == '.' || p[-1] == '_' || (p[-1] >= 'a' && p[-1] <= 'z'));
        char c = p[n];
        bool after = !(c == '.' || c == '_' || (c >= 'a' && c <= 'z'));
        if (before && after)
            return true;
    }
    return false;
}

static char *run_brume(const char *args)
{
    const char *out = test_tmp_path("help.txt");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s > %s", BRUME_EXE, args, out);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    return test_slurp(out, &n);
}

/* `brume help render` names every key; `brume options` and `brume help options` give each
 * one's values, default and meaning. */
TEST(help_lists_every_key)
{
    char *render = run_brume("help render");
    char *list = run_brume("options");
    char *help = run_brume("help options");
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        ASSERT_EQ_INT(brume_option_get(NULL, i, &o), BRUME_OK);
        if (!has_key(render, o.key))
            TEST_FAIL("`brume help render` does not name %s", o.key);
        char entry[512];
        snprintf(entry, sizeof entry, "%s\n    %s%s%s\n", o.key, o.values, o.default_value[0] ? "; default " : "",
                 o.default_value);
        ASSERT_CONTAINS(list, entry);
        ASSERT_CONTAINS(help, entry);
        char first[41];
        snprintf(first, sizeof first, "%s", o.doc);
        first[strcspn(first, " ")] = '\0';
        ASSERT_CONTAINS(strstr(list, entry) + strlen(entry), first);
    }
    free(render);
    free(list);
    free(help);
}

/* A value of option o as scene-file JSON: its default, or one of its values. */
static void json_value(const brume_option *o, char *out, size_t n)
{
    const char *v = o->default_value;
    if (o->kind == BRUME_OPTION_ENUM && !v[0])
        v = "paper"; /* blasi.variant has no default */
    if (o->kind == BRUME_OPTION_PATH)
        snprintf(out, n, "\"light.bin\"");
    else if (o->kind == BRUME_OPTION_ENUM)
        snprintf(out, n, "\"%s\"", v);
    else if (o->kind == BRUME_OPTION_COLOR)
        snprintf(out, n, "[%s, %s, %s]", v, v, v);
    else if (v[0] >= 'a' && v[0] <= 'z' && o->kind != BRUME_OPTION_BOOL)
        snprintf(out, n, "0.5"); /* computed ("from the phase function"): a value in range */
    else
        snprintf(out, n, "%s", v);
}

/* The scene reader's method objects and --set take every key of the tables, nested or
 * dotted, and refuse any other with the table's keys in the message. */
TEST(reader_takes_exactly_the_tables_keys)
{
    brume_context *ctx = brume_context_new();
    const char *file = test_tmp_path("opts.json");
    test_write_file(file, SCENE_HEAD "}");
    char known[METHOD_OPTIONS_COUNT][1024] = {{0}};
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        ASSERT_EQ_INT(brume_option_get(NULL, i, &o), BRUME_OK);
        char value[256], json[2048], nested[2048], set[512];
        json_value(&o, value, sizeof value);
        size_t mlen = strcspn(o.key, ".");
        const char *key = o.key + mlen + 1;
        snprintf(json, sizeof json, SCENE_HEAD ", \"%.*s\": {\"%s\": %s}}", (int)mlen, o.key, key, value);
        /* "a.b": v as {"a": {"b": v}} */
        const char *dot = strchr(key, '.');
        if (dot)
            snprintf(nested, sizeof nested, SCENE_HEAD ", \"%.*s\": {\"%.*s\": {\"%s\": %s}}}", (int)mlen, o.key,
                     (int)(dot - key), key, dot + 1, value);
        else
            snprintf(nested, sizeof nested, "%s", json);
        for (int k = 0; k < 2; k++) {
            brume_scene *s = NULL;
            if (brume_scene_load(ctx, &(brume_source){.path = "opts.json", .text = k ? nested : json}, NULL, &s) != BRUME_OK)
                TEST_FAIL("%s: %s", k ? nested : json, brume_context_last_error(ctx));
            brume_scene_release(s);
        }
        snprintf(set, sizeof set, "%s=%s", o.key, value);
        const char *overrides[] = {set};
        brume_scene *s = NULL;
        if (brume_scene_load(ctx, &(brume_source){.path = file}, &(brume_load_options){.overrides = overrides, .noverrides = 1}, &s) !=
            BRUME_OK)
            TEST_FAIL("--set %s: %s", set, brume_context_last_error(ctx));
        brume_scene_release(s);
        for (int m = 0; m < METHOD_OPTIONS_COUNT; m++) {
            const char *name = method_options_def_get((method_options_id)m)->method;
            if (strlen(name) == mlen && strncmp(name, o.key, mlen) == 0) {
                size_t len = strlen(known[m]);
                snprintf(known[m] + len, sizeof known[m] - len, "%s%s", len ? ", " : "", key);
            }
        }
    }
    for (int m = 0; m < METHOD_OPTIONS_COUNT; m++) {
        const char *name = method_options_def_get((method_options_id)m)->method;
        ASSERT_TRUE(known[m][0] != '\0'); /* every method with a table lists its keys publicly */
        char json[512], want[1200], set[128];
        ASSERT_TRUE(strlen(known[m]) < 1100);
        snprintf(json, sizeof json, SCENE_HEAD ", \"%s\": {\"no_such_key\": 1}}", name);
        brume_scene *s = NULL;
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "opts.json", .text = json}, NULL, &s), BRUME_ERROR_PARSE);
        snprintf(want, sizeof want, "%s.no_such_key: unknown key (known here: %.1100s)", name, known[m]);
        ASSERT_CONTAINS(brume_context_last_error(ctx), want);
        snprintf(set, sizeof set, "%s.no_such_key=1", name);
        const char *overrides[] = {set};
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = file}, &(brume_load_options){.overrides = overrides, .noverrides = 1}, &s),
                      BRUME_ERROR_PARSE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), want);
    }
    brume_option o;
    ASSERT_EQ_INT(brume_option_get(ctx, brume_option_count(), &o), BRUME_ERROR_RANGE);
    ASSERT_EQ_INT(brume_option_get(ctx, -1, &o), BRUME_ERROR_RANGE);
    brume_context_release(ctx);
}

TEST_MAIN(setter_follows_the_table, range_words_match_the_range, defaults_are_unchanged,
          blasi_variant_leaves_keys_given, messages_are_unchanged, header_lists_every_key, doc_is_generated,
          help_lists_every_key, reader_takes_exactly_the_tables_keys)
