#!/usr/bin/python3
# independent_slab_mc.py - a Monte Carlo of the plane-parallel slab that shares nothing with
# brume, to arbitrate between `brume slab` and a published figure (docs/validation.md).
#
#   /usr/bin/python3 bench/independent_slab_mc.py [PHOTONS] [SEED] [ALBEDO TAU G]
#
# Collimated beam at normal incidence on a slab of optical thickness TAU, index 1 on both
# sides, Henyey-Greenstein phase function; photon weights multiplied by the albedo at each
# collision (MCML style), roulette below 1e-3. Prints "Rd VALUE STDERR" and "Tt VALUE
# STDERR" (Tt includes the unscattered beam). Needs python3-numpy.
import sys

import numpy as np

N = int(sys.argv[1]) if len(sys.argv) > 1 else 4_000_000
rng = np.random.default_rng(int(sys.argv[2]) if len(sys.argv) > 2 else 1)
a, tau, g = (float(x) for x in sys.argv[3:6]) if len(sys.argv) > 5 else (0.9, 1.0, 0.8)
R = np.zeros(N); T = np.zeros(N)
z = np.zeros(N); mu = np.ones(N); w = np.ones(N); idx = np.arange(N)
while idx.size:
    s = -np.log(1.0 - rng.random(idx.size))
    zn = z + mu * s          # depth coordinate in optical units, slab 0..tau, going +z = deeper
    out_b = zn >= tau; out_t = zn <= 0
    T[idx[out_b]] += w[out_b]; R[idx[out_t]] += w[out_t]
    keep = ~(out_b | out_t)
    idx, z, mu, w = idx[keep], zn[keep], mu[keep], w[keep] * a
    # HG sample
    u = rng.random(idx.size)
    t = (1 - g*g) / (1 - g + 2*g*u)
    ct = (1 + g*g - t*t) / (2*g)
    ct = np.clip(ct, -1, 1)
    st = np.sqrt(1 - ct*ct); phi = 2*np.pi*rng.random(idx.size)
    mu = mu*ct + np.sqrt(np.maximum(0, 1 - mu*mu))*st*np.cos(phi)
    # roulette
    small = w < 1e-3
    surv = rng.random(idx.size) < 0.1
    w = np.where(small, np.where(surv, w*10, 0), w)
    k = w > 0
    idx, z, mu, w = idx[k], z[k], mu[k], w[k]
print("Rd %.6f %.6f" % (R.mean(), R.std()/np.sqrt(N)))
print("Tt %.6f %.6f" % (T.mean(), T.std()/np.sqrt(N)))
