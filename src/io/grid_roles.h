/* grid_roles.h - the names each role's grid goes by in fire and smoke files (grid_roles.c;
 * the public brume_grid_pick and brume_grid_role read them). */
#ifndef BRUME_IO_GRID_ROLES_H
#define BRUME_IO_GRID_ROLES_H

/* The role's names by precedence, NULL-terminated ("density", "temperature", "emission",
 * "albedo", "velocity"); NULL for an unknown role. */
const char *const *grid_role_list(const char *role);

#endif
