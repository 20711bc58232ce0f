#!/usr/bin/env python3
# make_corpus.py - writes the bad-input corpus of tests/bad/ (files and cases.txt), run by run_bad.c.
# The corpus is committed; rerun this after changing it: python3 tests/bad/make_corpus.py
import json, os, struct, shutil

HERE = os.path.dirname(os.path.abspath(__file__))
cases = []  # (group, name, exit, pattern, args)

def case(group, name, code, pattern, args):
    assert '|' not in args, name
    cases.append((group, name, code, pattern, args))

def write(rel, data):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = 'wb' if isinstance(data, bytes) else 'w'
    with open(path, mode) as f:
        f.write(data)

for d in ('scenes', 'grids', 'images', 'meshes', 'phases'):
    shutil.rmtree(os.path.join(HERE, d), ignore_errors=True)

RENDER = '-o {T}/out.png --quiet'

def base():
    return {
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
        "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1.0}],
        "media": [{"density": {"type": "constant", "value": 1.0}, "sigma_a": 0.1, "sigma_s": 1.0}],
        "render": {"width": 8, "height": 8, "spp": 1, "threads": 1},
    }

def scene(name, code, pattern, mutate=None, text=None, group='scene', extra=''):
    """A scene file scenes/NAME.json: base() changed by mutate(s), or raw text."""
    if text is None:
        s = base()
        if mutate:
            r = mutate(s)
            if isinstance(r, dict):
                s = r
        text = json.dumps(s)
    write('scenes/%s.json' % name, text)
    case(group, name, code, pattern, 'render {D}/scenes/%s.json %s%s' % (name, RENDER, extra))

def setp(path, value):
    """A mutator setting s[path...] = value (path as a list of keys and indices)."""
    def m(s):
        o = s
        for k in path[:-1]:
            o = o[k]
        o[path[-1]] = value
    return m

def med(key, value):
    return setp(['media', 0, key], value)

def dens(d):
    return med('density', d)

# ---- scene files: syntax, structure, camera ------------------------------------------------
scene('not_json', 1, 'not_json.json', text='{"camera": ')
scene('empty_file', 1, 'empty_file.json', text='')
scene('top_array', 1, 'top_array.json', text='[1, 2]')
scene('nul_byte', 1, 'NUL', text='{"camera": {}\x00}')
scene('unknown_top_key', 1, 'camerra', lambda s: s.update(camerra=1))
scene('missing_camera', 1, 'camera', lambda s: s.pop('camera'))
scene('camera_fov_400', 1, 'camera.fov', setp(['camera', 'fov'], 400))
scene('camera_fov_zero', 1, 'camera.fov', setp(['camera', 'fov'], 0))
scene('camera_fov_string', 1, 'camera.fov', setp(['camera', 'fov'], 'wide'))
scene('camera_position_short', 1, 'camera.position', setp(['camera', 'position'], [1, 2]))
scene('camera_position_string', 1, 'camera.position', setp(['camera', 'position'], [1, 2, 'a']))
scene('camera_up_zero', 1, 'camera.up', setp(['camera', 'up'], [0, 0, 0]))
scene('camera_look_at_position', 1, 'look_at', setp(['camera', 'look_at'], [0, 0, 4]))
scene('camera_aperture_negative', 1, 'aperture_radius', setp(['camera', 'aperture_radius'], -1))
scene('camera_focus_zero', 1, 'focus_distance', setp(['camera', 'focus_distance'], 0))
scene('camera_shutter_reversed', 1, 'camera.shutter', setp(['camera', 'shutter'], [1, 0]))
scene('camera_shutter_string', 1, 'camera.shutter', setp(['camera', 'shutter'], 'open'))
scene('camera_keyframes_string', 1, 'keyframes', setp(['camera', 'keyframes'], 'soon'))
scene('camera_huge_number', 1, 'camera.position', text='{"camera": {"position": [1e400, 0, 4], "look_at": [0, 0, 0], "fov": 40}}')
# messages stay on one line: control characters from the file are escaped, long keys cut
scene('key_newline', 1, r'fo\\nv', lambda s: s['camera'].update({'fo\nv': 1}))
scene('key_escape', 1, r'\\x1b\[31m', lambda s: s['camera'].update({'\x1b[31mred': 1}))
scene('key_carriage_return', 1, r'\\r', lambda s: s.update({'x\rclear': 1}))
scene('key_long', 1, r'kkkkkkkk\.\.\.', lambda s: s.update({'k' * 5000: 1}))
scene('type_with_newline', 1, r'laser\\nbeam', setp(['lights', 0, 'type'], 'laser\nbeam'))
scene('deep_nesting', 1, 'deep_nesting.json', text='[' * 2000 + ']' * 2000)

# ---- lights ----------------------------------------------------------------------------------
scene('lights_not_array', 1, 'lights', lambda s: s.update(lights={'a': 1}))
scene('light_type_unknown', 1, 'lights\\[0\\].type', setp(['lights', 0, 'type'], 'laser'))
scene('light_direction_zero', 1, 'direction', setp(['lights', 0, 'direction'], [0, 0, 0]))
scene('light_angular_radius_91', 1, 'angular_radius', setp(['lights', 0, 'angular_radius'], 91))
scene('light_angular_radius_negative', 1, 'angular_radius', setp(['lights', 0, 'angular_radius'], -1))
scene('light_irradiance_negative', 1, 'irradiance', setp(['lights', 0, 'irradiance'], -1))
scene('light_irradiance_color_short', 1, 'irradiance', setp(['lights', 0, 'irradiance'], [1, 2]))
scene('light_point_no_intensity', 1, 'intensity', setp(['lights', 0], {'type': 'point', 'position': [0, 2, 0]}))
scene('light_spot_cone_zero', 1, 'cone_angle', setp(['lights', 0], {'type': 'spot', 'position': [0, 2, 0], 'direction': [0, -1, 0], 'intensity': 1, 'cone_angle': 0}))
scene('light_spot_falloff_beyond', 1, 'falloff_start', setp(['lights', 0], {'type': 'spot', 'position': [0, 2, 0], 'direction': [0, -1, 0], 'intensity': 1, 'cone_angle': 20, 'falloff_start': 30}))
scene('light_spot_profile_decreasing', 1, 'profile', setp(['lights', 0], {'type': 'spot', 'position': [0, 2, 0], 'direction': [0, -1, 0], 'intensity': 1, 'profile': [[10, 1], [5, 1]]}))
scene('light_spot_profile_and_cone', 1, 'profile', setp(['lights', 0], {'type': 'spot', 'position': [0, 2, 0], 'direction': [0, -1, 0], 'intensity': 1, 'profile': [[0, 1], [5, 1]], 'cone_angle': 10}))
scene('light_sphere_radius_zero', 1, 'radius', setp(['lights', 0], {'type': 'sphere', 'position': [0, 2, 0], 'radius': 0, 'radiance': 1}))
scene('light_disk_direction_zero', 1, 'direction', setp(['lights', 0], {'type': 'disk', 'position': [0, 2, 0], 'direction': [0, 0, 0], 'radius': 1, 'radiance': 1}))
# a sun of 1e-8 degrees renders (as the point sun it tends to), and ends
scene('sun_tiny_radius_renders', 0, '', setp(['lights', 0, 'angular_radius'], 1e-8))

# ---- background ------------------------------------------------------------------------------
scene('background_negative', 1, 'background', lambda s: s.update(background=-1))
scene('background_file_missing', 1, 'background.file', lambda s: s.update(background={'file': 'missing.exr'}))
scene('background_color_and_file', 1, 'background', lambda s: s.update(background={'file': 'x.exr', 'color': 1}))
scene('background_scale_negative', 1, 'background.scale', lambda s: s.update(background={'color': 1, 'scale': -1}))
scene('background_file_not_image', 1, 'background.file', lambda s: s.update(background={'file': '../images/text.png'}))
scene('background_file_truncated_png', 1, 'background.file', lambda s: s.update(background={'file': '../images/truncated.png'}))
scene('background_unknown_key', 1, 'background', lambda s: s.update(background={'colour': 1}))

# ---- media and densities ---------------------------------------------------------------------
scene('media_not_array', 1, 'media', lambda s: s.update(media={}))
scene('media_too_many', 1, 'media', lambda s: s.update(media=s['media'] * 100))
scene('medium_no_density', 1, 'density', lambda s: s['media'][0].pop('density'))
scene('medium_sigma_a_negative', 1, 'sigma_a', med('sigma_a', -1))
scene('medium_sigma_s_huge', 1, 'sigma_s', med('sigma_s', 1e13))
scene('medium_unknown_key', 1, 'albedo', med('albedo', 0.5))
scene('density_type_unknown', 1, 'density.type', dens({'type': 'smoke'}))
scene('constant_negative', 1, 'value', dens({'type': 'constant', 'value': -1}))
scene('constant_too_large', 1, 'value', dens({'type': 'constant', 'value': 1e31}))
scene('constant_bounds_inverted', 1, 'bounds', dens({'type': 'constant', 'value': 1, 'bounds': [[1, 1, 1], [-1, -1, -1]]}))
scene('constant_bounds_shape', 1, 'bounds', dens({'type': 'constant', 'value': 1, 'bounds': [1, 2, 3]}))
scene('procedural_resolution_small', 1, 'resolution', dens({'type': 'procedural_cloud', 'resolution': 1}))
scene('procedural_resolution_large', 1, 'resolution', dens({'type': 'procedural_cloud', 'resolution': 100000}))
# hangs, reported in the issue: a huge constant density must end (its collisions are real)
scene('huge_density_ends', 0, '', dens({'type': 'constant', 'value': 1e18}))
scene('huge_density_far_away_ends', 0, '', lambda s: (dens({'type': 'constant', 'value': 1e18, 'bounds': [[1e6 - 1, -1, -1], [1e6 + 1, 1, 1]]})(s), s['camera'].update(position=[1e6, 0, 4], look_at=[1e6, 0, 0])))
scene('huge_density_blasi_ends', 0, '', lambda s: (dens({'type': 'constant', 'value': 1e18})(s), s['render'].update(method='blasi'), s.update(blasi={'light_rays': 1000, 'r': 0, 'sources': 1}), s['media'][0].update(sigma_a=0)))
# a 20-byte raw grid with one voxel of 3e38 passes `brume info`; in a scene it is refused
scene('grid_hot_voxel', 1, 'media\\[0\\].*(optical depth|extinction)', dens({'type': 'grid', 'file': '../grids/hot_voxel.raw', 'dims': [5, 1, 1]}))
scene('grid_hot_voxel_1e6', 1, 'media\\[0\\].*optical depth', dens({'type': 'grid', 'file': '../grids/warm_voxel.raw', 'dims': [5, 1, 1]}))
scene('grid_missing_file_key', 1, 'file', dens({'type': 'grid'}))
scene('grid_file_missing', 1, 'media\\[0\\].density.file', dens({'type': 'grid', 'file': 'nothing.vol'}))
scene('grid_format_unknown', 1, 'format', dens({'type': 'grid', 'file': '../grids/ok.vol', 'format': 'xyz'}))
scene('grid_dims_zero', 1, 'dims', dens({'type': 'grid', 'file': '../grids/ok.vol', 'dims': [0, 1, 1]}))
scene('grid_dims_fraction', 1, 'dims', dens({'type': 'grid', 'file': '../grids/ok.vol', 'dims': [1.5, 1, 1]}))
scene('grid_dims_huge', 1, 'dims', dens({'type': 'grid', 'file': '../grids/ok.vol', 'dims': [70000, 1, 1]}))
scene('grid_scale_zero', 1, 'scale', dens({'type': 'grid', 'file': '../grids/ok.vol', 'scale': 0}))
scene('grid_max_memory_small', 1, 'max_memory_mb', dens({'type': 'grid', 'file': '../grids/ok.vol', 'max_memory_mb': 0.5}))
scene('grid_transform_bad', 1, 'transform', dens({'type': 'grid', 'file': '../grids/ok.vol', 'transform': {'scale': 0}}))
scene('grid_filter_unknown', 1, 'filter', dens({'type': 'grid', 'file': '../grids/ok.vol', 'filter': 'cubic'}))
scene('grid_vol_trailing', 1, 'trailing bytes', dens({'type': 'grid', 'file': '../grids/vol_trailing.vol'}))
scene('grid_raw_sidecar_inverted', 1, 'min < max', dens({'type': 'grid', 'file': '../grids/inverted.raw'}))
scene('grid_raw_contradicts_sidecar', 1, 'bytes, but', dens({'type': 'grid', 'file': '../grids/short.raw'}))
scene('grid_raw_nan', 1, 'grids/nan.raw', dens({'type': 'grid', 'file': '../grids/nan.raw', 'dims': [2, 1, 1]}))
scene('grid_is_directory', 1, 'media\\[0\\].density.file', dens({'type': 'grid', 'file': '../grids'}))
scene('fractal_dims_zero', 1, 'dims', dens({'type': 'fractal_cloud', 'dims': [0, 8, 8]}))
scene('fractal_dims_huge', 1, 'dims', dens({'type': 'fractal_cloud', 'dims': [2000, 8, 8]}))
scene('fractal_method_unknown', 1, 'method', dens({'type': 'fractal_cloud', 'dims': [8, 8, 8], 'method': 'magic'}))
scene('fractal_octaves_17', 1, 'octaves', dens({'type': 'fractal_cloud', 'dims': [8, 8, 8], 'octaves': 17}))
scene('fractal_hurst_one', 1, 'hurst', dens({'type': 'fractal_cloud', 'dims': [8, 8, 8], 'hurst': 1}))
scene('fractal_shape_unknown', 1, 'shape', dens({'type': 'fractal_cloud', 'dims': [8, 8, 8], 'shape': 'cube'}))
# one memory limit over every generator (render.max_memory_mb)
scene('memory_fractal_over_budget', 1, 'render.max_memory_mb', lambda s: (dens({'type': 'fractal_cloud', 'dims': [512, 512, 512], 'method': 'midpoint'})(s), s['render'].update(max_memory_mb=64)))
scene('memory_fractal_1024_default', 1, 'render.max_memory_mb', dens({'type': 'fractal_cloud', 'dims': [1024, 1024, 1024], 'method': 'spectral'}))
scene('memory_grid_over_budget', 1, 'memory limit', lambda s: (dens({'type': 'grid', 'file': '../grids/big.vol'})(s), s['render'].update(max_memory_mb=1)))
scene('memory_max_memory_mb_zero', 1, 'max_memory_mb', lambda s: s['render'].update(max_memory_mb=0))
scene('memory_stam_lattice', 1, 'render.max_memory_mb', lambda s: (dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 0.3]]})(s), s['render'].update(max_memory_mb=16), s.update(stam={'lattice': 512, 'eps': 0.2, 'voxelize': {'resolution': 8}})))

# ---- blobs -----------------------------------------------------------------------------------
scene('blobs_none', 1, 'no blobs', dens({'type': 'blobs'}))
scene('blobs_short_entry', 1, 'blobs\\[0\\]', dens({'type': 'blobs', 'blobs': [[1, 2, 3]]}))
scene('blobs_zero_radius', 1, 'blobs\\[0\\]', dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 0]]}))
scene('blobs_negative_mass', 1, 'blobs\\[1\\]', dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 1], [0, 0, 0, -1, 1]]}))
scene('blobs_not_array', 1, 'blobs', dens({'type': 'blobs', 'blobs': 3}))
scene('blobs_cutoff_20', 1, 'cutoff', dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 1]], 'cutoff': 20}))
scene('blobs_generator_unknown', 1, 'generators\\[0\\]', dens({'type': 'blobs', 'generators': [{'type': 'rain'}]}))
scene('blobs_cloud_radii_zero', 1, 'radii', dens({'type': 'blobs', 'generators': [{'type': 'cloud', 'center': [0, 0, 0], 'radii': 0}]}))
scene('blobs_cloud_count_huge', 1, 'count', dens({'type': 'blobs', 'generators': [{'type': 'cloud', 'center': [0, 0, 0], 'radii': 1, 'count': 5000000}]}))
scene('blobs_fire_band_reversed', 1, 'band', dens({'type': 'blobs', 'generators': [{'type': 'fire', 'base': [0, 0, 0], 'band': [0.5, 0.2]}]}))
# the work bomb of the issue: four million blobs from a 200-byte scene, refused up front
scene('blobs_work_bomb', 1, 'majorant grid', dens({'type': 'blobs', 'generators': [{'type': 'cloud', 'center': [0, 0, 0], 'radii': 1, 'count': 4194304, 'h': [0.2, 0.4]}]}))
scene('blobs_cluster_bomb', 1, 'clouds x count', dens({'type': 'blobs', 'generators': [{'type': 'cluster', 'bounds_min': [-1, -1, -1], 'bounds_max': [1, 1, 1], 'radii_min': 0.1, 'radii_max': 0.2, 'clouds': 100000, 'count': 4194304}]}))
scene('blobs_velocity_bad', 1, 'velocity', dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 1]], 'velocity': [1, 2]}))

# ---- phase functions and tables --------------------------------------------------------------
def phase(name, code, pattern, p, group='phase'):
    scene(name, code, pattern, med('phase', p), group=group)

phase('phase_type_unknown', 1, 'phase.type', {'type': 'mie'})
phase('phase_hg_g_one', 1, 'phase.g', {'type': 'hg', 'g': 1})
phase('phase_schlick_k_and_g', 1, 'exactly one of k and g', {'type': 'schlick', 'k': 0.1, 'g': 0.1})
phase('phase_schlick_mix_r_two', 1, 'phase.r', {'type': 'schlick_mix', 'r': 2, 'k': 0, 'kprime': 0})
phase('phase_mixture_empty', 1, 'lobes', {'type': 'mixture', 'lobes': []})
phase('phase_mixture_too_many', 1, 'lobes', {'type': 'mixture', 'lobes': [{'weight': 1, 'phase': {'type': 'isotropic'}}] * 17})
phase('phase_mixture_weight_negative', 1, 'lobes\\[0\\].weight', {'type': 'mixture', 'lobes': [{'weight': -1, 'phase': {'type': 'isotropic'}}]})
phase('phase_mixture_nested_unknown', 1, 'lobes\\[0\\].phase', {'type': 'mixture', 'lobes': [{'weight': 1, 'phase': {'type': 'x'}}]})
phase('phase_mixture_weights_zero', 1, 'phase', {'type': 'mixture', 'lobes': [{'weight': 0, 'phase': {'type': 'isotropic'}}]})
phase('table_missing', 1, 'missing.txt', {'type': 'tabulated', 'file': 'missing.txt'})
# the issue's /dev/zero (one endless line, 8.4 GB): inputs are regular files, read within limits
phase('table_dev_zero', 1, '/dev/zero: not a regular file', {'type': 'tabulated', 'file': '/dev/zero'})
phase('table_dev_urandom', 1, '/dev/urandom: not a regular file', {'type': 'tabulated', 'file': '/dev/urandom'})
phase('table_decreasing', 1, 'angles must increase', {'type': 'tabulated', 'file': '../phases/decreasing.txt'})
phase('table_angle_200', 1, 'angle 200', {'type': 'tabulated', 'file': '../phases/angle200.txt'})
phase('table_negative_value', 1, 'value -1', {'type': 'tabulated', 'file': '../phases/negative.txt'})
phase('table_one_row', 1, 'one_row.txt', {'type': 'tabulated', 'file': '../phases/one_row.txt'})
phase('table_garbage', 1, 'expected an angle', {'type': 'tabulated', 'file': '../phases/garbage.txt'})
phase('table_three_columns', 1, 'unexpected', {'type': 'tabulated', 'file': '../phases/three.txt'})
phase('table_missing_value', 1, 'expected a value', {'type': 'tabulated', 'file': '../phases/novalue.txt'})
phase('table_all_zero', 1, 'all_zero.txt', {'type': 'tabulated', 'file': '../phases/all_zero.txt'})
phase('table_nul_byte', 1, 'NUL', {'type': 'tabulated', 'file': '../phases/nul.txt'})
phase('table_long_line', 1, 'line longer', {'type': 'tabulated', 'file': '../phases/long_line.txt'})
phase('table_infinite_value', 1, 'value', {'type': 'tabulated', 'file': '../phases/inf.txt'})
phase('table_stdin', 1, '/dev/stdin', {'type': 'tabulated', 'file': '/dev/stdin'})
phase('table_is_directory', 1, 'not a regular file \\(a folder\\)', {'type': 'tabulated', 'file': '../phases'})
write('phases/decreasing.txt', '0 1\n10 1\n5 1\n')
write('phases/angle200.txt', '0 1\n200 1\n')
write('phases/negative.txt', '0 1\n90 -1\n180 1\n')
write('phases/one_row.txt', '0 1\n')
write('phases/garbage.txt', 'hello world\n')
write('phases/three.txt', '0 1 2\n180 1\n')
write('phases/novalue.txt', '0\n180 1\n')
write('phases/all_zero.txt', '0 0\n90 0\n180 0\n')
write('phases/nul.txt', b'0 1\n\x0090 1\n180 1\n')
write('phases/long_line.txt', '0 1\n' + ' ' * 5000 + '90 1\n180 1\n')
write('phases/inf.txt', '0 1\n90 inf\n180 1\n')

# ---- surfaces and meshes ---------------------------------------------------------------------
def surf(name, code, pattern, sf, group='scene'):
    scene(name, code, pattern, lambda s: s.update(surfaces=sf), group=group)

surf('surfaces_not_array', 1, 'surfaces', {'type': 'plane'})
surf('surface_type_unknown', 1, 'surfaces\\[0\\]', [{'type': 'torus'}])
surf('surface_plane_normal_zero', 1, 'normal', [{'type': 'plane', 'point': [0, -1, 0], 'normal': [0, 0, 0]}])
surf('surface_sphere_radius_negative', 1, 'radius', [{'type': 'sphere', 'radius': -1}])
surf('surface_box_inverted', 1, 'surfaces\\[0\\]', [{'type': 'box', 'min': [1, 1, 1], 'max': [0, 0, 0]}])
surf('surface_albedo_above_one', 1, 'albedo', [{'type': 'sphere', 'radius': 0.5, 'material': {'albedo': 2}}])
surf('surface_material_unknown_key', 1, 'material', [{'type': 'sphere', 'radius': 0.5, 'material': {'colour': 1}}])
for nm, f, pat in [('mesh_missing', 'missing.obj', 'missing.obj'),
                   ('mesh_garbage', '../meshes/garbage.obj', 'garbage.obj'),
                   ('mesh_no_triangles', '../meshes/points.obj', 'points.obj'),
                   ('mesh_bad_index', '../meshes/bad_index.obj', 'bad_index.obj'),
                   ('mesh_nan_vertex', '../meshes/nan.obj', 'nan.obj'),
                   ('mesh_empty', '../meshes/empty.obj', 'empty.obj'),
                   ('mesh_ply_truncated', '../meshes/truncated.ply', 'truncated.ply'),
                   ('mesh_stl_truncated', '../meshes/truncated.stl', 'truncated.stl'),
                   ('mesh_unknown_extension', '../meshes/shape.xyz', 'shape.xyz'),
                   ('mesh_directory', '../meshes', 'meshes')]:
    surf(nm, 1, pat, [{'type': 'mesh', 'file': f}], group='mesh')
write('meshes/garbage.obj', 'this is not a mesh\n\x01\x02\n')
write('meshes/points.obj', 'v 0 0 0\nv 1 0 0\np 1\np 2\n')
write('meshes/bad_index.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n')
write('meshes/nan.obj', 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n')
write('meshes/empty.obj', '')
write('meshes/truncated.ply', 'ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\nproperty float z\nelement face 1000\nproperty list uchar int vertex_indices\nend_header\n' + '\x00' * 40)
write('meshes/truncated.stl', b'\x00' * 80 + struct.pack('<I', 1000000) + b'\x00' * 100)
# assimp runs in a child process under time and memory limits (io/mesh.c); what is
# cheap to see is refused before it starts
write('meshes/ply_no_end_header.ply', 'ply\nformat ascii 1.0\n')  # 21 bytes: assimp spun forever
write('meshes/ply_type_typo.ply', b'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n'
      b'property float y\nproperty flaot z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n'
      + struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<B3i', 3, 0, 1, 2))  # an assimp assertion
write('meshes/obj_huge_polygon.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf' + ' 1 2 3' * 1700 + '\n')  # quadratic
def nested_gltf(levels, width):
    """A glTF whose every level instances the one below `width` times: width^levels triangles."""
    nodes, below = [{'mesh': 0}], 0
    for _ in range(levels):
        first = len(nodes)
        nodes += [{'children': [below]} for _ in range(width)]
        nodes.append({'children': list(range(first, first + width))})
        below = len(nodes) - 1
    import base64
    data = base64.b64encode(struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0)).decode()
    return json.dumps({'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [below]}], 'nodes': nodes,
                       'meshes': [{'primitives': [{'attributes': {'POSITION': 0}}]}],
                       'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 3, 'type': 'VEC3',
                                      'min': [0, 0, 0], 'max': [1, 1, 0]}],
                       'bufferViews': [{'buffer': 0, 'byteLength': 36}],
                       'buffers': [{'byteLength': 36, 'uri': 'data:application/octet-stream;base64,' + data}]})
write('meshes/gltf_nested.gltf', nested_gltf(4, 50))  # 6.25 million instances: 5.8 GB in assimp
for nm, f, pat in [('mesh_ply_no_end_header', '../meshes/ply_no_end_header.ply', 'ply_no_end_header.ply: .*end_header'),
                   ('mesh_ply_type_typo', '../meshes/ply_type_typo.ply', "ply_type_typo.ply: .*unknown property type 'flaot'"),
                   ('mesh_obj_huge_polygon', '../meshes/obj_huge_polygon.obj', 'obj_huge_polygon.obj: .*a face of 5100 vertices')]:
    surf(nm, 1, pat, [{'type': 'mesh', 'file': f}], group='mesh')
def gltf_64mb(s):
    s['surfaces'] = [{'type': 'mesh', 'file': '../meshes/gltf_nested.gltf'}]
    s['render']['max_memory_mb'] = 64
scene('mesh_gltf_nested_instances', 1, 'gltf_nested.gltf', gltf_64mb, group='mesh')
def glb(text):
    """A binary glTF 2.0 (.glb) of the glTF text: its JSON chunk (padded with spaces), its buffer 0 the BIN chunk."""
    doc = json.loads(text)
    import base64
    binary = base64.b64decode(doc['buffers'][0].pop('uri').split(',', 1)[1])
    data = json.dumps(doc).encode()
    data += b' ' * (-len(data) % 4)
    binary += b'\0' * (-len(binary) % 4)
    return (struct.pack('<4sII', b'glTF', 2, 12 + 8 + len(data) + 8 + len(binary)) + struct.pack('<I4s', len(data), b'JSON')
            + data + struct.pack('<I4s', len(binary), b'BIN\0') + binary)
write('meshes/gltf_nested.glb', glb(nested_gltf(4, 50)))  # the same instances, binary: counted alike
def glb_64mb(s):
    s['surfaces'] = [{'type': 'mesh', 'file': '../meshes/gltf_nested.glb'}]
    s['render']['max_memory_mb'] = 64
scene('mesh_glb_nested_instances', 1, r'gltf_nested\.glb: its instances flattened make 1\.88e\+07 vertices', glb_64mb,
      group='mesh')
write('meshes/shape.xyz', '1 2 3\n')

# ---- render settings -------------------------------------------------------------------------
def rset(name, code, pattern, key, value):
    scene(name, code, pattern, setp(['render', key], value))

rset('render_width_zero', 1, 'render.width', 'width', 0)
rset('render_width_huge', 1, 'render.width', 'width', 70000)
rset('render_spp_zero', 1, 'render.spp', 'spp', 0)
rset('render_method_unknown', 1, 'render.method', 'method', 'magic')
rset('render_max_depth_zero', 1, 'max_depth', 'max_depth', 0)
rset('render_fps_zero', 1, 'fps', 'fps', 0)
rset('render_threads_negative', 1, 'threads', 'threads', -1)
rset('render_seed_negative', 1, 'seed', 'seed', -1)
rset('render_seed_fraction', 1, 'seed', 'seed', 1.5)
rset('render_filter_unknown', 1, 'render.filter', 'filter', {'type': 'lanczos'})
rset('render_unknown_key', 1, 'samples', 'samples', 4)
rset('render_max_memory_tiny', 1, 'max_memory_mb', 'max_memory_mb', 0.25)

# ---- path, blasi and stam options -------------------------------------------------------------
def path(name, code, pattern, opts):
    scene(name, code, pattern, lambda s: s.update(path=opts))

path('path_sun_lobe_negative', 1, 'path.sun_lobe', {'sun_lobe': -1})
path('path_sun_lobe_huge', 1, 'path.sun_lobe', {'sun_lobe': 1e9})
path('path_sun_lobe_text', 1, 'path.sun_lobe', {'sun_lobe': 'many'})
path('path_split_zero', 1, 'path.split', {'split': 0})
path('path_split_fraction', 1, 'path.split', {'split': 2.5})
path('path_split_huge', 1, 'path.split', {'split': 1e9})
path('path_unknown_key', 1, 'path.clamp', {'clamp': 3})
scene('path_not_object', 1, 'path', lambda s: s.update(path=3))

# ---- blasi and stam options ------------------------------------------------------------------
def blasi(name, code, pattern, opts, method='blasi'):
    scene(name, code, pattern, lambda s: (s.update(blasi=opts), s['render'].update(method=method)))

blasi('blasi_r_two', 1, 'blasi.r', {'r': 2})
blasi('blasi_step_negative', 1, 'blasi.step', {'step': -1})
blasi('blasi_threshold_one', 1, 'blasi.threshold', {'threshold': 1})
blasi('blasi_sources_zero', 1, 'blasi.sources', {'sources': 0})
blasi('blasi_light_rays_zero', 1, 'blasi.light_rays', {'light_rays': 0})
blasi('blasi_exit_unknown', 1, 'blasi.exit_deposit', {'exit_deposit': 'later'})
blasi('blasi_variant_unknown', 1, 'blasi.variant', {'variant': 'other'})
blasi('blasi_unknown_key', 1, 'blasi', {'rays': 3})
blasi('blasi_step_tiny', 1, 'blasi.step', {'step': 1e-300})
blasi('blasi_load_missing', 1, 'missing.bl', {'load_light': 'missing.bl'})
# writes: a scene file writes only inside its own folder
blasi('save_light_absolute', 1, 'blasi.save_light.*absolute', {'save_light': '/tmp/brume-bad-escape.bl', 'light_rays': 100})
blasi('save_light_parent', 1, 'blasi.save_light.*\\.\\.', {'save_light': '../escape.bl', 'light_rays': 100})
blasi('save_light_inner_parent', 1, 'blasi.save_light.*\\.\\.', {'save_light': 'a/../../escape.bl', 'light_rays': 100})
blasi('save_light_symlink', 1, 'blasi.save_light.*symbolic link', {'save_light': 'link_to_tmp/escape.bl', 'light_rays': 100})
blasi('save_light_no_folder', 1, 'blasi.save_light', {'save_light': 'no/such/folder/x.bl', 'light_rays': 100})
blasi('save_light_empty', 1, 'blasi.save_light', {'save_light': '', 'light_rays': 100})
os.symlink('/tmp', os.path.join(HERE, 'scenes', 'link_to_tmp'))

def stam(name, code, pattern, opts):
    scene(name, code, pattern, lambda s: (dens({'type': 'blobs', 'blobs': [[0, 0, 0, 1, 0.3]]})(s), s.update(stam=opts), s['render'].update(method='stam')))

stam('stam_eps_negative', 1, 'stam.eps', {'eps': -1})
stam('stam_lattice_one', 1, 'stam.lattice', {'lattice': 1})
stam('stam_lattice_huge', 1, 'stam.lattice', {'lattice': 1000})
stam('stam_steps_zero', 1, 'stam.steps', {'steps': 0})
stam('stam_light_grid_huge', 1, 'stam.light_grid', {'light_grid': 1000})
stam('stam_unknown_key', 1, 'stam', {'speed': 1})
stam('stam_voxelize_negative', 1, 'voxelize', {'voxelize': {'resolution': -1}})
scene('stam_on_grid', 1, 'stam', lambda s: s['render'].update(method='stam'))
scene('keyframes_medium_bad', 1, 'keyframes', med('keyframes', [{'time': 'a'}]))
scene('keyframes_light_bad', 1, 'keyframes', setp(['lights', 0, 'keyframes'], 7))

# ---- grids (brume info) ----------------------------------------------------------------------
def grid(name, data, code, pattern, ext, sidecar=None, args='info'):
    fn = 'grids/%s.%s' % (name, ext)
    write(fn, data)
    if sidecar is not None:
        write(fn + '.hdr', sidecar)
    case('grid', 'grid_' + name, code, pattern, '%s {D}/%s' % (args, fn))

f32 = lambda *v: struct.pack('<%df' % len(v), *v)
def vol(dims, box=(0, 0, 0, 1, 1, 1), enc=1, ch=1, data=None, magic=b'VOL\x03'):
    n = dims[0] * dims[1] * dims[2] if min(dims) > 0 else 0
    body = data if data is not None else (f32(*([0.5] * n)) if enc == 1 else b'\x80' * n)
    return magic + struct.pack('<I3iI', enc, dims[0], dims[1], dims[2], ch) + f32(*box) + body

write('grids/ok.vol', vol((2, 2, 2)))
write('grids/big.vol', vol((128, 128, 64), data=b''))  # claims 4 MiB of voxels: over a 1 MiB budget, refused unread
write('grids/hot_voxel.raw', f32(0, 0, 3e38, 0, 0))  # the issue's 20 bytes
write('grids/warm_voxel.raw', f32(0, 0, 1e6, 0, 0))
write('grids/inverted.raw', f32(*([0.5] * 8)))
write('grids/inverted.raw.hdr', 'dims 2 2 2\nbounds 1 0 0 0 1 1\n')
write('grids/short.raw', f32(*([0.5] * 7)))
write('grids/short.raw.hdr', 'dims 2 2 2\n')
write('grids/nan.raw', f32(float('nan'), 1))
grid('vol_trailing', vol((2, 2, 2)) + b'\x00\x00\x00\x00', 1, 'trailing bytes', 'vol')
grid('vol_trailing_one_byte', vol((2, 2, 2)) + b'\x00', 1, 'trailing bytes', 'vol')
grid('vol_truncated', vol((2, 2, 2))[:-4], 1, 'truncated', 'vol')
grid('vol_header_truncated', vol((2, 2, 2))[:20], 1, 'truncated', 'vol')
grid('vol_bad_magic', vol((2, 2, 2), magic=b'VOX\x03'), 1, 'magic', 'vol')
grid('vol_version_2', vol((2, 2, 2), magic=b'VOL\x02'), 1, 'version 3', 'vol')
grid('vol_encoding_2', vol((2, 2, 2), enc=2, data=b''), 1, 'encoding 2', 'vol')
grid('vol_channels_3', vol((2, 2, 2), ch=3), 1, '3 channels', 'vol')
grid('vol_dims_zero', vol((0, 2, 2), data=b''), 1, 'dimension 0', 'vol')
grid('vol_dims_negative', vol((-5, 2, 2), data=b''), 1, 'dimension -5', 'vol')
grid('vol_dims_huge', vol((2000000000, 2000000000, 2), data=b''), 1, 'overflow|memory limit', 'vol')
grid('vol_dims_over_memory', vol((2048, 2048, 1024), data=b''), 1, 'memory limit', 'vol')
grid('vol_box_empty', vol((2, 2, 2), box=(0, 0, 0, 0, 1, 1)), 1, 'bounding box', 'vol')
grid('vol_box_nan', vol((2, 2, 2), box=(float('nan'), 0, 0, 1, 1, 1)), 1, 'bounding box', 'vol')
grid('vol_nan_voxel', vol((2, 1, 1), data=f32(float('nan'), 0)), 1, 'vol_nan_voxel.vol', 'vol')
grid('vol_negative_voxel', vol((2, 1, 1), data=f32(-1, 0)), 1, 'vol_negative_voxel.vol', 'vol')
grid('vol_inf_voxel', vol((2, 1, 1), data=f32(float('inf'), 0)), 1, 'vol_inf_voxel.vol', 'vol')
grid('vol_empty', b'', 1, 'vol_empty.vol', 'vol')
grid('raw_not_cube', f32(1, 2, 3), 1, 'needs dimensions', 'raw')
grid('raw_odd_size', b'\x00' * 7, 1, 'raw_odd_size.raw', 'raw')
grid('raw_empty', b'', 1, 'raw_empty.raw', 'raw')
grid('raw_sidecar_inverted', f32(*([0.5] * 8)), 1, 'min < max', 'raw', 'dims 2 2 2\nbounds 0 1 0 1 0 1\n')
grid('raw_sidecar_nan_bounds', f32(*([0.5] * 8)), 1, 'min < max', 'raw', 'dims 2 2 2\nbounds nan 0 0 1 1 1\n')
grid('raw_sidecar_flat', f32(*([0.5] * 8)), 1, 'min < max', 'raw', 'dims 2 2 2\nbounds 0 0 0 1 1 0\n')
grid('raw_sidecar_contradicts', f32(*([0.5] * 8)), 1, 'bytes, but', 'raw', 'dims 4 4 4\n')
grid('raw_sidecar_bad_line', f32(*([0.5] * 8)), 1, 'expected dims', 'raw', 'size 2 2 2\n')
grid('raw_sidecar_no_dims', f32(*([0.5] * 8)), 1, 'no dims', 'raw', '# nothing\n')
grid('raw_sidecar_bounds_first', f32(*([0.5] * 8)), 1, 'bounds before dims', 'raw', 'bounds 0 0 0 1 1 1\ndims 2 2 2\n')
grid('raw_sidecar_matrix_short', f32(*([0.5] * 8)), 1, '12 numbers', 'raw', 'dims 2 2 2\nvoxel_to_world 1 0 0 0 1 0 0 0 1 0 0\n')
grid('raw_sidecar_singular', f32(*([0.5] * 8)), 1, 'raw_sidecar_singular', 'raw', 'dims 2 2 2\nvoxel_to_world 0 0 0 0 0 0 0 0 0 0 0 0\n')
grid('raw_sidecar_dims_negative', f32(*([0.5] * 8)), 1, 'dimension', 'raw', 'dims -2 2 2\n')
grid('raw_nan', f32(float('nan'), 1, 1, 1, 1, 1, 1, 1), 1, 'raw_nan.raw', 'raw')
grid('raw_negative', f32(-1, 1, 1, 1, 1, 1, 1, 1), 1, 'raw_negative.raw', 'raw')
grid('df3_header_short', b'\x00\x02\x00', 1, 'truncated df3 header', 'df3')
grid('df3_body_wrong', b'\x00\x02\x00\x02\x00\x02' + b'\x01' * 9, 1, 'bytes each', 'df3')
grid('df3_dims_zero', b'\x00\x00\x00\x02\x00\x02', 1, 'dimension 0', 'df3')
grid('df3_trailing', b'\x00\x02\x00\x02\x00\x02' + b'\x01' * 8 + b'\x01' * 3, 1, 'bytes each', 'df3')
grid('nvdb_garbage', b'garbage!' * 8, 1, 'nvdb_garbage.nvdb', 'nvdb')
grid('nvdb_truncated', b'NanoVDB0'[:5], 1, 'nvdb_truncated.nvdb', 'nvdb')
grid('unknown_extension', b'\x00' * 64, 1, 'unknown grid format', 'xyz')
case('grid', 'grid_missing_file', 1, 'nothing.vol', 'info {D}/grids/nothing.vol')
case('grid', 'grid_directory', 1, 'grids', 'info {D}/grids')
case('grid', 'grid_info_two_files', 2, 'info', 'info {D}/grids/ok.vol {D}/grids/ok.vol')
case('grid', 'convert_to_unknown', 2, '--to', 'convert {D}/grids/ok.vol {T}/x.raw --to xyz')
case('grid', 'convert_missing_input', 1, 'nothing.vol', 'convert {D}/grids/nothing.vol {T}/x.raw')
case('grid', 'convert_no_folder', 1, 'no/such', 'convert {D}/grids/ok.vol {T}/no/such/x.raw')
case('grid', 'convert_df3_over_one', 1, 'df3', 'convert {D}/grids/warm_voxel.raw {T}/x.df3 --dims 5x1x1')
case('grid', 'convert_bad_input', 1, 'trailing bytes', 'convert {D}/grids/vol_trailing.vol {T}/x.raw')

# ---- images (brume compare reads them) -------------------------------------------------------
def image(name, data, pattern, ext):
    fn = 'images/%s.%s' % (name, ext)
    write(fn, data)
    case('image', 'image_' + name, 1, pattern, 'compare {D}/%s {D}/images/ok.pfm' % fn)

def pfm(w, h, scale=-1.0, data=None, magic='PF'):
    body = data if data is not None else f32(*([0.5] * (w * h * 3)))
    return ('%s\n%d %d\n%g\n' % (magic, w, h, scale)).encode() + body

write('images/ok.pfm', pfm(2, 2))
PNG_HDR = b'\x89PNG\r\n\x1a\n'
write('images/text.png', 'not an image\n')
write('images/truncated.png', PNG_HDR + b'\x00\x00\x00\x0dIHDR\x00\x00\x04\x00\x00\x00\x04\x00\x08\x06\x00\x00\x00')
image('pfm_trailing', pfm(2, 2) + b'\x00' * 4, 'trailing bytes', 'pfm')
image('pfm_truncated', pfm(2, 2)[:-4], 'truncated', 'pfm')
image('pfm_huge', pfm(100000, 100000, data=b''), 'image size', 'pfm')
image('pfm_zero', pfm(0, 2, data=b''), 'image size', 'pfm')
image('pfm_bad_magic', pfm(2, 2, magic='P6'), 'pfm_bad_magic.pfm', 'pfm')
image('pfm_scale_zero', pfm(2, 2, scale=0.0), 'pfm_scale_zero.pfm', 'pfm')
image('pfm_nan_pixel', pfm(1, 1, data=f32(float('nan'), 0, 0)), 'pfm_nan_pixel.pfm', 'pfm')
image('pfm_header_garbage', b'PF\nabc def\n-1\n', 'pfm_header_garbage.pfm', 'pfm')
image('png_text', b'not an image\n', 'png_text.png', 'png')
image('png_truncated', PNG_HDR + b'\x00\x00\x00\x0dIHDR\x00\x00\x04\x00\x00\x00\x04\x00\x08\x06\x00\x00\x00', 'png_truncated.png', 'png')
image('png_signature_only', PNG_HDR, 'png_signature_only.png', 'png')
image('png_huge_claim', PNG_HDR + b'\x00\x00\x00\x0dIHDR\x00\x01\x00\x00\x00\x01\x00\x00\x08\x06\x00\x00\x00' + b'\x00' * 16, 'png_huge_claim.png', 'png')
image('exr_garbage', b'\x76\x2f\x31\x01' + b'\x00' * 60, 'exr_garbage.exr', 'exr')
image('exr_text', b'hello', 'exr_text.exr', 'exr')
image('empty_png', b'', 'empty_png.png', 'png')
image('unknown_extension', b'\x00' * 16, 'unknown_extension.bmp', 'bmp')
case('image', 'image_missing', 1, 'nothing.png', 'compare {D}/images/nothing.png {D}/images/ok.pfm')
case('image', 'image_size_mismatch', 1, '2 x 2 but the reference is 1 x 1', 'compare {D}/images/ok.pfm {D}/images/pfm1x1.pfm')
write('images/pfm1x1.pfm', pfm(1, 1))

# ---- command lines ---------------------------------------------------------------------------
def cli(name, code, pattern, args):
    case('cli', name, code, pattern, args)

S = '{D}/scenes/sun_tiny_radius_renders.json -o {T}/o.png --quiet'
cli('unknown_command', 2, 'unknown command', 'paint')
cli('help_unknown', 2, 'unknown command', 'help paint')
cli('render_spp_zero', 2, '--spp', 'render %s --spp 0' % S)
cli('render_spp_equals_zero', 2, '--spp', 'render %s --spp=0' % S)
cli('render_spp_text', 2, '--spp', 'render %s --spp many' % S)
cli('render_spp_overflow', 2, '--spp', 'render %s --spp 99999999999999999999' % S)
cli('render_spp_plus', 2, '--spp', 'render %s --spp +4' % S)
cli('render_spp_space', 2, '--spp', 'render %s --spp \\s4' % S)
cli('render_spp_equals_ok', 0, '', 'render %s --spp=4' % S)  # the issue: --key=value is accepted
cli('render_width_equals_ok', 0, '', 'render %s --width=4 --height=4' % S)
cli('render_width_negative', 2, '--width', 'render %s --width -1' % S)
cli('render_seed_negative', 2, '--seed', 'render %s --seed -1' % S)
cli('render_seed_equals_negative', 2, '--seed', 'render %s --seed=-1' % S)
cli('render_seed_overflow', 2, '--seed', 'render %s --seed 18446744073709551616' % S)
cli('render_threads_huge', 2, '--threads', 'render %s --threads 2000' % S)
cli('render_max_depth_zero', 2, '--max-depth', 'render %s --max-depth 0' % S)
cli('render_frames_reversed', 2, '--frames', 'render %s --frames 5-2' % S)
cli('render_frames_overflow', 2, '--frames', 'render %s --frames 0-99999999999999999999' % S)
cli('render_frames_no_pattern', 2, 'frame', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/o.png --frames 0-1 --quiet')
cli('render_pattern_width_overflow', 2, 'width at most 99', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/out_%99999999999d.png --frames 0-1 --quiet')
cli('render_pattern_two', 2, '-o', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/a%d%d.png --frames 0-1 --quiet')
cli('render_pattern_s', 2, '-o', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/a%s.png --frames 0-1 --quiet')
cli('render_shard_bad', 2, '--shard', 'render %s --shard 3/2' % S)
cli('render_method_unknown', 1, 'method', 'render %s --method magic' % S)
cli('render_exposure_huge', 2, '--exposure', 'render %s --exposure 100' % S)
cli('render_set_no_equals', 2, '--set', 'render %s --set blasi.r' % S)
cli('render_set_unknown', 1, 'blasi.nokey', 'render %s --set blasi.nokey=1' % S)
cli('render_set_equals_range', 1, 'blasi.r', 'render %s --set=blasi.r=2' % S)
cli('render_set_path_sun_lobe', 1, 'path.sun_lobe', 'render %s --set path.sun_lobe=-0.5' % S)
cli('render_set_path_split', 1, 'path.split', 'render %s --set path.split=9' % S)
cli('render_unknown_flag', 2, '--bogus', 'render %s --bogus' % S)
cli('render_unknown_flag_equals', 2, '--bogus', 'render %s --bogus=1' % S)
cli('render_missing_value', 2, '-o', 'render {D}/scenes/sun_tiny_radius_renders.json -o')
cli('render_two_scenes', 2, 'more than one scene', 'render %s {D}/scenes/empty_file.json' % S)
cli('render_scene_missing', 1, 'nothing.json', 'render {D}/scenes/nothing.json -o {T}/o.png')
cli('render_scene_name_escape', 1, r'\\x1b\[31m', 'render {D}/\\e[31mred.json -o {T}/o.png')
cli('render_scene_name_newline', 1, r'a\\nb', 'render {D}/a\\nb.json -o {T}/o.png')
cli('render_flag_escape', 2, r'\\x1b', 'render %s --\\e[2J' % S)
cli('render_output_folder_is_a_file', 1, 'not a folder', 'render {D}/scenes/sun_tiny_radius_renders.json -o {D}/cases.txt/o.png --quiet')
cli('render_output_unknown_type', 1, 'o.bmp', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/o.bmp --quiet')
cli('render_video_no_pattern', 2, 'video', 'render {D}/scenes/sun_tiny_radius_renders.json -o {T}/o.png --video {T}/v.mp4 --quiet')
cli('gen_no_kind', 2, 'gen', 'gen')
cli('gen_seed_negative', 2, '--seed', 'gen cloud --seed -1 -o {T}/c.raw')  # the issue: wrapped to 2^64 - 1
cli('gen_seed_equals_negative', 2, '--seed', 'gen cloud --seed=-1 -o {T}/c.raw')
cli('gen_seed_float', 2, '--seed', 'gen cloud --seed 1e3 -o {T}/c.raw')
cli('gen_seed_overflow', 2, '--seed', 'gen cloud --seed 99999999999999999999999 -o {T}/c.raw')
cli('gen_octaves_20', 2, '--octaves', 'gen cloud --octaves 20 -o {T}/c.raw')
cli('gen_dims_zero', 2, '--dims', 'gen cloud --dims 0 -o {T}/c.raw')
cli('gen_dims_bad', 2, '--dims', 'gen cloud --dims 5x5 -o {T}/c.raw')
cli('gen_dims_overflow', 2, '--dims', 'gen cloud --dims 99999999999 -o {T}/c.raw')
cli('gen_method_unknown', 2, '--method', 'gen cloud --method magic -o {T}/c.raw')
cli('gen_bounds_inverted', 2, '--bounds', 'gen cloud --bounds 1,1,1,0,0,0 -o {T}/c.raw')
cli('gen_unknown_flag', 2, '--bogus', 'gen cloud --bogus 1 -o {T}/c.raw')
cli('gen_missing_value', 2, '--seed', 'gen cloud --seed')
cli('info_no_file', 2, 'info', 'info')
cli('info_unknown_flag', 2, '--bogus', 'info --bogus')
cli('convert_no_args', 2, 'convert', 'convert')
cli('convert_unknown_flag', 2, '--bogus', 'convert --bogus')
cli('convert_dims_overflow', 2, '--dims', 'convert {D}/grids/hot_voxel.raw {T}/x.vol --dims 99999999999x1x1')
cli('compare_missing', 2, 'compare', 'compare')
cli('compare_scale_bad', 2, '--scale', 'compare {D}/images/ok.pfm {D}/images/ok.pfm --scale -1')
cli('slab_albedo_two', 2, '--albedo', 'slab --albedo 2')
cli('slab_tau_negative', 2, '--tau', 'slab --tau -1')
cli('slab_samples_negative', 2, '--samples', 'slab --samples -1')
cli('slab_max_depth_equals_zero', 2, '--max-depth', 'slab --max-depth=0')
cli('slab_phase_unknown', 1, 'magic', 'slab --albedo 0.5 --tau 1 --phase magic --samples 10')
cli('phase_unknown_sub', 2, 'phase', 'phase dance')
cli('phase_fit_unknown', 1, 'zzz', 'phase fit zzz')
cli('phase_plot_unknown_option', 2, '--bogus', 'phase plot --bogus')

# ---- resources, outputs, checkpoints -------------------------------------------------------
write('images/env_negative.pfm', pfm(2, 1, data=f32(0.5, 0.5, 0.5, 0.5, -1.0, 0.5)))
write('images/env_inf.pfm', pfm(2, 1, data=f32(0.5, 0.5, 0.5, float('inf'), 0.5, 0.5)))
scene('background_file_negative', 1, r'background.*pixel \(1, 0\) G is -1', lambda s: s.update(background={'file': '../images/env_negative.pfm'}))
scene('background_file_inf', 1, r'background.*pixel \(1, 0\) R is inf', lambda s: s.update(background={'file': '../images/env_inf.pfm'}))
def work_bomb(s):
    s['render']['method'] = 'blasi'
    s['media'][0]['density'] = {'type': 'procedural_cloud', 'resolution': 32}
    s['blasi'] = {'step': 1e-6}  # 17 hours at the default light rays
scene('blasi_step_work_bomb', 1, r'render\.max_work \(1e\+12\)', work_bomb)
def film_bomb(s):
    s['render'].update(width=4096, height=4096, max_memory_mb=1)
scene('film_over_memory_limit', 1, r'render\.max_memory_mb: a 4096 x 4096 render needs [0-9]+ bytes for its film', film_bomb)
write('grids/raw_32_bytes.raw', b'\x00' * 32)
def huge_dims(s):
    s['media'][0]['density'] = {'type': 'grid', 'file': '../grids/raw_32_bytes.raw', 'format': 'raw', 'dims': [65536, 65536, 1]}
    s['render']['max_memory_mb'] = 1
scene('grid_message_64bit', 1, '65536 x 65536 x 1 voxels need 17179869184 bytes, over the memory limit of 1048576', huge_dims, group='grid')
cli('resume_dev_zero', 1, '/dev/zero: not a regular file', 'render ' + S + ' --resume /dev/zero')
cli('resume_not_a_checkpoint', 1, 'ok.pfm: not a brume checkpoint', 'render ' + S + ' --resume {D}/images/ok.pfm')
cli('checkpoint_is_a_folder', 1, r'--checkpoint: .*not a regular file \(a folder\)', 'render ' + S + ' --checkpoint {T}')
cli('save_light_is_a_folder', 1, r'--save-light: .*not a regular file \(a folder\)', 'render ' + S + ' --method blasi --save-light {T}')
cli('figures_out_is_a_file', 1, r'figures: -o .*ok\.pfm: not a folder', 'figures -o {D}/images/ok.pfm --quick')
cli('stam_light_cache_over_max_work', 1, r'stam\.light_grid: .* units of work, over render\.max_work \(1e\+03\)',
    'render {D}/../../scenes/stam-compare.json -o {T}/o.png --quiet --width 8 --height 8 --spp 1 --set render.max_work=1000 --set stam.eps=0')  # no random field: the light cache is the first work
# work bounded like memory: each generator estimates its work before it starts
scene('procedural_cloud_over_max_work', 1,
      r'procedural_cloud_over_max_work\.json: media\[0\]\.density: .*64\^3 voxels x 5 octaves of noise are 1\.31e\+06 units of work, over render\.max_work \(1e\+05\)',
      lambda s: (dens({'type': 'procedural_cloud', 'resolution': 64})(s), s['render'].update(max_work=1e5)))
scene('fractal_cloud_over_max_work', 1,
      r'fractal_cloud_over_max_work\.json: media\[0\]\.density: .*fractal cloud: 64 x 64 x 64 voxels .* units of work, over render\.max_work \(1e\+05\)',
      lambda s: (dens({'type': 'fractal_cloud', 'dims': [64, 64, 64]})(s), s['render'].update(max_work=1e5)))
cli('stam_random_field_over_max_work', 1, r'stam-compare\.json: stam: stam\.lattice: the random field.s 64 x 64 x 64 lattice points are 4\.98e\+06 units of work',
    'render {D}/../../scenes/stam-compare.json -o {T}/o.png --quiet --width 8 --height 8 --spp 1 --set stam.lattice=64 --set render.max_work=1e6')
cli('checkpoint_is_a_device', 1, r'--checkpoint: /dev/null: not a regular file', 'render ' + S + ' --checkpoint /dev/null')

# ---- extreme but finite numbers: refused in one line with the limit exact (tests/test_hostile_numbers.c) ----
scene('camera_aperture_beyond_ray_tracing', 1, r'camera: position \(0, 0, 4\) and aperture_radius .* 1e\+30 put ray origins .* beyond the 1e\+18',
      setp(['camera', 'aperture_radius'], 1e30))
scene('camera_position_beyond_ray_tracing', 1, r'camera: position \(2e\+18, 0, 4\) .* beyond the 1e\+18',
      setp(['camera', 'position'], [2e18, 0, 4]))
scene('camera_key_aperture_beyond_ray_tracing', 1, r'camera\.keyframes\[1\]: .* beyond the 1e\+18',
      setp(['camera', 'keyframes'], [{'time': 0, 'aperture_radius': 0}, {'time': 1, 'aperture_radius': 5e18}]))
scene('render_spp_one_over', 1, r'render\.spp: 16777217 outside \[1, 16777216\]', setp(['render', 'spp'], 16777217))
scene('chromatic_channels_beyond_tracking', 1, r'media\[0\]: sigma_t from .* across the colour channels',
      lambda s: (dens({'type': 'constant', 'value': 1, 'bounds': [[-1, -1, -1], [1, 1, 1]]})(s),
                 med('sigma_a', [1e12, 1e-3, 1e-3])(s), med('sigma_s', [1e12, 1, 1])(s)))
scene('chromatic_clear_channel_beyond_tracking', 1, r'media\[0\]: sigma_t from 0 to 300000 across the colour channels',
      lambda s: (dens({'type': 'constant', 'value': 1, 'bounds': [[-1, -1, -1], [1, 1, 1]]})(s),
                 med('sigma_a', 0)(s), med('sigma_s', [3e5, 3e5, 0])(s)))
scene('fractal_wind_times_time_beyond_lattice', 1, r'fractal: at time 1000000 s the noise reaches lattice coordinate .* beyond 1e9',
      dens({'type': 'fractal_cloud', 'dims': [4, 4, 4], 'turbulence': 0.5, 'wind': [1e6, 0, 0], 'time': 1e6}))
write('scenes/pbrt_lensradius_beyond_ray_tracing.pbrt',
      'LookAt 0 0 4  0 0 0  0 1 0\nCamera "perspective" "float fov" [40] "float lensradius" [1e30]\n'
      'Film "rgb" "integer xresolution" [8] "integer yresolution" [8]\nWorldBegin\n'
      'LightSource "distant" "point3 from" [0 1 0] "point3 to" [0 0 0]\nShape "sphere" "float radius" [1]\n')
case('scene', 'pbrt_lensradius_beyond_ray_tracing', 1, r'pbrt_lensradius_beyond_ray_tracing\.pbrt: camera: .*lensradius.* beyond the 1e\+18',
     'render {D}/scenes/pbrt_lensradius_beyond_ray_tracing.pbrt ' + RENDER)

with open(os.path.join(HERE, 'cases.txt'), 'w') as f:
    f.write('# cases.txt - the bad-input corpus, written by make_corpus.py (edit that, then rerun it).\n')
    f.write('# GROUP|NAME|EXIT|ARGS|PATTERN; run by run_bad.c (see its header).\n')
    for g, n, e, pat, a in cases:
        f.write('%s|%s|%d|%s|%s\n' % (g, n, e, a, pat))
print(len(cases), 'cases')
