/* cli_gen_sparse.h - `brume gen fire` and `brume gen upres` (cli_gen_sparse.c): sparse
 * volumes worth rendering, made without downloads. */
#ifndef BRUME_CLI_GEN_SPARSE_H
#define BRUME_CLI_GEN_SPARSE_H

/* argv[0] is "fire" / "upres"; exit codes as every command (0, 1, 2). */
int gen_fire(int argc, char **argv);
int gen_upres(int argc, char **argv);

#endif
