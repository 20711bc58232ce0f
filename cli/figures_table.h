/* figures_table.h - the captions of `brume figures`, for the test that checks them against
 * the scenes they describe (tests/test_papers.c, captions_match_the_scenes). */
#ifndef BRUME_CLI_FIGURES_TABLE_H
#define BRUME_CLI_FIGURES_TABLE_H

/* The caption of figure `name` ("stam-fig5-a") and, through *scene when not NULL, the scene
 * file's name without ".json" for figures rendered from a scene (else ""); NULL when there is
 * no such figure. The strings are static. */
const char *figures_caption(const char *name, const char **scene);

#endif
