/* majorant_body.h - a walk over a cell grid's majorants (density/density.h) over one real
 * type (core/real_names.h): majorant_grid_cell, majorant_next in double over majorant_iter,
 * majorant_grid_cellf, majorant_nextf in float over majorant_iterf (render/track_float.h),
 * which has the same fields but the NanoVDB tree's. The includer declares its
 * RN(majorant_cell_next) first: the double one also walks the NanoVDB tree. */
#include "core/real_names.h"

#ifndef GRID_INDEX
#define GRID_INDEX size_t
#endif
#ifndef GRID_LOAD
#define GRID_LOAD(p) (*(p))
#endif

/* The next cell of a cell grid's walk (it->dda over the cells it->mn) and its bounds. */
static inline __attribute__((always_inline)) bool RN(majorant_grid_cell)(RN(majorant_iter) *it, RN(majorant_seg) *seg)
{
    RN(grid_dda_step) st;
    if (!RN(grid_dda_next)(&it->dda, &st))
        return false;
#if !defined(__CUDA_ARCH__)
    it->cells++;
#endif
    seg->t0 = st.t0;
    seg->t1 = st.t1;
    const GRID_INDEX n0 = (GRID_INDEX)it->mn[0], n1 = (GRID_INDEX)it->mn[1];
    const GRID_INDEX c = (GRID_INDEX)st.i + n0 * ((GRID_INDEX)st.j + n1 * (GRID_INDEX)st.k);
    seg->rho_maj = (R)GRID_LOAD(&it->maj[c]);
    seg->rho_min = it->mino ? (R)GRID_LOAD(&it->mino[c]) : RC(0.0);
    seg->rho_ctl = it->mean ? (R)GRID_LOAD(&it->mean[c]) : seg->rho_min;
    return true;
}

/* Starts the walk of a cell grid's majorants (maj, mino, mean over mn cells, each NULL but
 * maj meaning none) along the ray o + t d in cell space over [tmin, tmax], within the box
 * [wlo, whi) of cell space: the box of the non-empty cells clipped to the voxels'. */
static inline __attribute__((always_inline)) void RN(majorant_grid_begin)(RN(majorant_iter) *it, const float *maj,
                                                                          const float *mino, const float *mean,
                                                                          const int mn[3], const R wlo[3],
                                                                          const R whi[3], RN(vec3) o, RN(vec3) d,
                                                                          R tmin, R tmax)
{
    it->maj = maj;
    it->mino = mino;
    it->mean = mean;
    it->has_next = false;
    it->cells = 0;
    it->by_ctl = false;
    for (int a = 0; a < 3; a++)
        it->mn[a] = mn[a];
    RN(grid_dda_dir) w;
    RN(grid_dda_dir_make)(&w, d);
    if (!RN(grid_dda_begin_clip_dir)(&it->dda, mn, wlo, whi, o, &w, tmin, tmax))
        it->dda.done = true;
}

/* Consecutive cells with the same majorant come out as one segment: empty space (0) and
 * uniform regions cost one segment each. The float instantiation (the GPU's stages) walks
 * cell by cell instead: the merge's look-ahead segment costs a GPU thread 15 of its 96
 * registers (docs/gpu.md, "Single precision"). The tentative collisions are the same either
 * way (the tracking loop carries its exponential across segments); a residual walk's control
 * is then each cell's mean rather than the merged cells' mean, as unbiased. */
static inline __attribute__((always_inline)) bool RN(majorant_next)(RN(majorant_iter) *it, RN(majorant_seg) *seg)
{
#if REAL_F
    return RN(majorant_cell_next)(it, seg);
#else
    if (it->has_next) {
        *seg = it->next;
        it->has_next = false;
    } else if (!RN(majorant_cell_next)(it, seg)) {
        return false;
    }
    RN(majorant_seg) s;
    const bool by_ctl = it->by_ctl;
    R ctl_len = by_ctl ? seg->rho_ctl * (seg->t1 - seg->t0) : RC(0.0); /* the integral of the controls */
    bool merged = false;
    while (RN(majorant_cell_next)(it, &s)) {
        if (s.rho_maj == seg->rho_maj && s.rho_min == seg->rho_min) {
            if (by_ctl)
                ctl_len += s.rho_ctl * (s.t1 - s.t0);
            seg->t1 = s.t1;
            merged = true;
        } else {
            it->next = s;
            it->has_next = true;
            break;
        }
    }
    if (by_ctl && merged) /* the merged cells' mean, within the bounds (rounding) */
        seg->rho_ctl = R_FMAX(seg->rho_min, R_FMIN(seg->rho_maj, ctl_len / (seg->t1 - seg->t0)));
    return true;
#endif
}

#include "core/real_names_end.h"
