# raw_to_vdb.py - writes cloud64.raw (64^3 float32, x fastest, cell-centred on
# [-0.5, 0.5]^3) as an OpenVDB fog volume with grid "density", for Blender.
#   python3 bench/cycles/raw_to_vdb.py cloud64.raw cloud64.vdb
# Uses Debian's python3-openvdb and python3-numpy.
import sys

import numpy as np
import pyopenvdb as vdb

raw, out = sys.argv[1], sys.argv[2]
n = 64
a = np.fromfile(raw, dtype="<f4").reshape((n, n, n))  # [k][j][i]
a = np.ascontiguousarray(a.transpose(2, 1, 0))  # [i][j][k]: copyFromArray indexes (x, y, z)
g = vdb.FloatGrid()
g.copyFromArray(a)
g.name = "density"
g.gridClass = vdb.GridClass.FOG_VOLUME
# index (i, j, k) -> world -0.5 + (i + 0.5) / 64: voxel size 1/64, then a shift of the
# index-space origin (OpenVDB places voxel centres at integer index coordinates).
xf = vdb.createLinearTransform(voxelSize=1.0 / n)
xf.translate((-0.5 + 0.5 / n,) * 3)
g.transform = xf
vdb.write(out, grids=[g])
