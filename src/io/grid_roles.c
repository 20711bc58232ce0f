/* grid_roles.c - the role brume gives each grid of a .vdb/.nvdb file by its name, as the
 * tools that write fire and smoke name them (Houdini's pyro, EmberGen, Blender's fluid
 * cache): what a medium's field takes when the scene names no grid for it, and what
 * `brume info` lists (docs/grids.md, "Fire files: grids by name"). */
#include <string.h>

#include "io/grid_roles.h"

#include "brume.h"

/* Each role's names, by precedence: the first one the file has, with a fitting value type,
 * is the role's grid. */
static const char *const density_names[] = {"density", "smoke", "soot", NULL};
static const char *const temperature_names[] = {"temperature", "temp", "heat", NULL};
static const char *const emission_names[] = {"flame", "flames", "fire", "emission", NULL};
static const char *const albedo_names[] = {"Cd", "color", "albedo", NULL};
static const char *const velocity_names[] = {"vel", "v", "velocity", NULL};

static const struct {
    const char *role;
    const char *const *names;
    bool vec3_only; /* the grid must hold vec3 values (else float ones, or either for emission) */
    bool either;
} roles[] = {
    {"density", density_names, false, false},   {"temperature", temperature_names, false, false},
    {"emission", emission_names, false, true},  {"albedo", albedo_names, true, false},
    {"velocity", velocity_names, true, false},
};

static bool is_vec3(const char *type) { return strncmp(type, "vec3", 4) == 0; }

static bool fits(int r, const brume_grid_entry *e)
{
    bool v = is_vec3(e->type), f = strcmp(e->type, "float") == 0;
    return roles[r].either ? (v || f) : (roles[r].vec3_only ? v : f);
}

static int role_index(const char *role)
{
    for (int r = 0; r < (int)(sizeof roles / sizeof roles[0]); r++)
        if (strcmp(roles[r].role, role) == 0)
            return r;
    return -1;
}

int brume_grid_pick(const brume_grid_entry *grids, int count, const char *role)
{
    int r = role ? role_index(role) : -1;
    if (r < 0 || !grids)
        return -1;
    for (const char *const *nm = roles[r].names; *nm; nm++)
        for (int i = 0; i < count; i++)
            if (strcmp(grids[i].name, *nm) == 0 && fits(r, &grids[i]))
                return i;
    return -1;
}

const char *brume_grid_role(const brume_grid_entry *grids, int count, int index)
{
    if (!grids)
        return NULL;
    if (index < 0 || index >= count)
        return "";
    for (int r = 0; r < (int)(sizeof roles / sizeof roles[0]); r++)
        if (brume_grid_pick(grids, count, roles[r].role) == index)
            return roles[r].role;
    return "";
}

const char *const *grid_role_list(const char *role)
{
    int r = role ? role_index(role) : -1;
    return r < 0 ? NULL : roles[r].names;
}

const char *brume_grid_role_names(const char *role)
{
    static const char *const lists[] = {"density, smoke, soot", "temperature, temp, heat",
                                        "flame, flames, fire, emission", "Cd, color, albedo", "vel, v, velocity"};
    if (!role)
        return NULL;
    int r = role_index(role);
    return r < 0 ? "" : lists[r];
}
