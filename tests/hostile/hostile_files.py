# hostile_files.py - the file classes of the hostile corpus (pbrt, grids, meshes, images,
# checkpoints) and the command lines, HTTP requests and signals; called by make_hostile.py,
# whose header gives the expectations' rules.
import base64, json, struct, zlib

NAN, INF = float('nan'), float('inf')


def f32(*v):
    return struct.pack('<%df' % len(v), *v)


# ---- .pbrt ---------------------------------------------------------------------------------
PBRT = '''LookAt 0 0 4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Sampler "sobol" "integer pixelsamples" [ 1 ]
Integrator "volpath" "integer maxdepth" [ 20 ]
WorldBegin
LightSource "distant" "point3 to" [ 0 -1 0 ] "rgb L" [ 1 1 1 ]
MakeNamedMedium "fog" "string type" "uniformgrid" "integer nx" [ 2 ] "integer ny" [ 2 ] "integer nz" [ 2 ]
  "point3 p0" [ -1 -1 -1 ] "point3 p1" [ 1 1 1 ] "float density" [ 1 1 1 1 1 1 1 1 ]
  "rgb sigma_a" [ 0.1 0.1 0.1 ] "rgb sigma_s" [ 1 1 1 ] "float scale" [ 1 ]
AttributeBegin
  MediumInterface "fog" ""
  Material "interface"
  Shape "sphere" "float radius" [ 1 ]
AttributeEnd
'''
PBRT_NUMBERS = [('fov', '"float fov" [ 40 ]', '"float fov" [ %s ]', (0.001, 179)),
                ('xres', '"integer xresolution" [ 8 ]', '"integer xresolution" [ %s ]', (1, 65536, 'int', 4096)),
                ('spp', '"integer pixelsamples" [ 1 ]', '"integer pixelsamples" [ %s ]', (1, 16777216, 'int', 64)),
                ('maxdepth', '"integer maxdepth" [ 20 ]', '"integer maxdepth" [ %s ]', (1, 100000, 'int')),
                # sigma_s x scale over a grid's majorant cell meets the spread limit well below 1e12
                ('scale', '"float scale" [ 1 ]', '"float scale" [ %s ]', (0, 1e12, 'either', 1e4)),
                ('lens', '"float fov" [ 40 ]', '"float fov" [ 40 ] "float lensradius" [ %s ]', (0, 1e18, 'either', 1e17))]
PBRT_VALUES = ['0', '-0', '1', '-1', '0.5', '40', '1e-308', '1e308', '1e30', '1e18', '1e19', '179', '180',
               '2147483647', '2147483648', '99999999999999999999', '65537', '16777217', '100001',
               'nan', 'inf', '-inf', '1e999', '0x10', '1,5', '"40"', 'true', '']


def judge_pbrt(text, lim):
    try:
        v = float(text)
    except ValueError:
        return 'refuse'
    if text.lower() in ('nan', 'inf', '-inf') or v != v or abs(v) == INF:
        return 'refuse'
    lo, hi = lim[0], lim[1]
    kind = lim[2] if len(lim) > 2 else None
    if kind == 'int' and (not text.lstrip('-').isdigit()):
        return 'refuse'
    if v < lo or v > hi:
        return 'refuse'
    if kind == 'int' and len(lim) > 3 and v > lim[3]:
        return 'slow'
    if kind == 'either' and v > lim[3]:
        return 'either'
    return 'image'


def pbrt_cases(render_scene):
    render_scene('pbrt_valid', 'pbrt', 'image', PBRT, ext='pbrt', folder='pbrt')
    for label, old, new, lim in PBRT_NUMBERS:
        for i, v in enumerate(PBRT_VALUES):
            expect = judge_pbrt(v, lim)
            render_scene('pbrt_%s_%02d' % (label, i), 'pbrt', expect, PBRT.replace(old, new % v), ext='pbrt', folder='pbrt',
                         note='%s = %s' % (label, v))
    # cut inside a string or a bracket: never a whole file
    inside, depth, quote = [], 0, False
    for i, ch in enumerate(PBRT):
        if ch == '"':
            quote = not quote
        elif ch == '[' and not quote:
            depth += 1
        elif ch == ']' and not quote:
            depth -= 1
        if quote or depth > 0:
            inside.append(i + 1)  # PBRT[:i + 1] ends inside the string or the bracket
    for c in inside[::9]:
        render_scene('pbrt_cut_%04d' % c, 'pbrt', 'refuse', PBRT[:c], ext='pbrt', folder='pbrt')
    bad = {
        'unknown_directive': PBRT + 'Frobnicate 1 2 3\n',
        'camera_in_world': PBRT + 'Camera "perspective" "float fov" [ 30 ]\n',
        'unterminated_string': PBRT + 'Shape "sphere\n',
        'unterminated_bracket': PBRT + 'Shape "sphere" "float radius" [ 1\n',
        'attribute_end_alone': PBRT + 'AttributeEnd\n',
        'fov_twice': PBRT.replace('"float fov" [ 40 ]', '"float fov" [ 40 ] "float fov" [ 30 ]'),
        'lookat_eye_is_look': PBRT.replace('LookAt 0 0 4', 'LookAt 0 0 0'),
        'lookat_short': PBRT.replace('LookAt 0 0 4  0 0 0  0 1 0', 'LookAt 0 0 4  0 0 0'),
        'scale_zero': PBRT.replace('LookAt', 'Scale 0 0 0\nLookAt'),
        'scale_1e300': PBRT.replace('LookAt', 'Scale 1e300 1e300 1e300\nLookAt'),
        'transform_nan': PBRT.replace('LookAt', 'Transform [ nan 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 ]\nLookAt'),
        'transform_short': PBRT.replace('LookAt', 'Transform [ 1 0 0 ]\nLookAt'),
        'include_dev_zero': 'Include "/dev/zero"\n' + PBRT,
        'include_itself': 'Include "include_itself.pbrt"\n' + PBRT,
        'include_missing': 'Include "nothing.pbrt"\n' + PBRT,
        'param_type_unknown': PBRT.replace('"float fov"', '"quaternion fov"'),
        'param_no_name': PBRT.replace('"float fov"', '"float"'),
        'medium_unknown': PBRT.replace('MediumInterface "fog"', 'MediumInterface "smog"'),
        'medium_type_unknown': PBRT.replace('"uniformgrid"', '"plasma"'),
        'sigma_negative': PBRT.replace('"rgb sigma_s" [ 1 1 1 ]', '"rgb sigma_s" [ -1 1 1 ]'),
        'sigma_short': PBRT.replace('"rgb sigma_s" [ 1 1 1 ]', '"rgb sigma_s" [ 1 1 ]'),
        'nul_byte': PBRT.replace('WorldBegin', 'World\x00Begin'),
        'binary_garbage': bytes(range(256)) * 4,
        'comment_only': '# nothing\n',
        'empty': '',
        'world_twice': PBRT + 'WorldBegin\n',
        'deep_attributes': PBRT + 'AttributeBegin\n' * 3000 + 'AttributeEnd\n' * 3000,
    }
    for name, text in bad.items():
        render_scene('pbrt_' + name, 'pbrt', 'refuse', text, ext='pbrt', folder='pbrt')


# ---- grids ---------------------------------------------------------------------------------
def vol(dims, box=(0, 0, 0, 1, 1, 1), enc=1, ch=1, data=None, magic=b'VOL\x03'):
    n = dims[0] * dims[1] * dims[2] if min(dims) > 0 else 0
    body = data if data is not None else f32(*([0.5] * n))
    return magic + struct.pack('<I3iI', enc, dims[0], dims[1], dims[2], ch) + f32(*box) + body


def df3(dims, data=None):
    n = dims[0] * dims[1] * dims[2]
    return struct.pack('>3H', *dims) + (data if data is not None else b'\x80' * n)


VOXELS = [(0.0, 'ok'), (-0.0, 'ok'), (1e-45, 'ok'), (1.0, 'ok'), (1e6, 'either'), (1e30, 'either'), (3e38, 'either'),
          (NAN, 'refuse'), (INF, 'refuse'), (-INF, 'refuse'), (-1.0, 'refuse'), (-1e-45, 'refuse')]


def grid_file(case, write, name, data, expect, ext, sidecar=None, note=''):
    path = write('grids/%s.%s' % (name, ext), data)
    if sidecar is not None:
        write('grids/%s.%s.hdr' % (name, ext), sidecar)
    case('grid_info_' + name, 'grid', expect, ['info', path], note=note)
    return path


def grid_cases(case, write, render_scene, base):
    good = vol((2, 2, 2))
    grid_file(case, write, 'vol_ok', good, 'ok', 'vol')
    for i, (v, e) in enumerate(VOXELS):
        grid_file(case, write, 'vol_voxel_%02d' % i, vol((2, 2, 2), data=f32(*([0.5] * 7 + [v]))), e, 'vol', note='voxel %r' % v)
        grid_file(case, write, 'raw_voxel_%02d' % i, f32(*([0.5] * 7 + [v])), e, 'raw', note='voxel %r' % v)
    for i, d in enumerate([(0, 2, 2), (-1, 2, 2), (2, 2, -2), (2 ** 31 - 1, 2, 2), (65536, 65536, 65536), (1, 1, 2 ** 30),
                           (3, 2, 2), (1, 1, 1)]):
        body = f32(*([0.5] * 8))
        e = 'ok' if d == (1, 1, 1) else 'refuse'
        grid_file(case, write, 'vol_dims_%02d' % i, vol(d, data=body if d != (1, 1, 1) else f32(0.5)), e, 'vol', note='dims %r' % (d,))
    for i, box in enumerate([(0, 0, 0, 0, 1, 1), (1, 1, 1, 0, 0, 0), (0, 0, 0, NAN, 1, 1), (0, 0, 0, INF, 1, 1),
                             (-1e30, -1e30, -1e30, 1e30, 1e30, 1e30), (0, 0, 0, 1e-30, 1e-30, 1e-30)]):
        e = 'refuse' if i < 4 else 'either'
        grid_file(case, write, 'vol_box_%02d' % i, vol((2, 2, 2), box=box), e, 'vol', note='box %r' % (box,))
    for cut in range(0, len(good), 4):
        grid_file(case, write, 'vol_cut_%03d' % cut, good[:cut], 'refuse', 'vol')
    for i, (enc, ch) in enumerate([(0, 1), (2, 1), (1, 0), (1, 2), (1, 4), (2 ** 31, 1), (1, 2 ** 31)]):
        grid_file(case, write, 'vol_format_%02d' % i, vol((2, 2, 2), enc=enc, ch=ch), 'refuse', 'vol', note='encoding %d channels %d' % (enc, ch))
    grid_file(case, write, 'vol_trailing_3', good + b'\0\0\0', 'refuse', 'vol')
    # raw: the size says the cube, or a sidecar says the dims
    for i, (n, e) in enumerate([(0, 'refuse'), (1, 'ok'), (7, 'refuse'), (27, 'ok'), (9, 'refuse')]):
        grid_file(case, write, 'raw_count_%02d' % i, f32(*([0.5] * n)), e, 'raw', note='%d floats' % n)
    grid_file(case, write, 'raw_odd_bytes', f32(*([0.5] * 8)) + b'\0', 'refuse', 'raw')
    sidecars = [('dims 2 2 2\n', 'ok'), ('dims 2 2 2\nbounds 0 0 0 1 1 1\n', 'ok'), ('dims 2 2\n', 'refuse'), ('dims 2 2 2 2\n', 'refuse'),
                ('dims 0 2 4\n', 'refuse'), ('dims 1 2 4\n', 'ok'), ('dims 4 2 1\n', 'ok'), ('dims 2 2 3\n', 'refuse'),
                ('dims -2 -2 2\n', 'refuse'), ('dims 2 2 2\nbounds 0 0 0 nan 1 1\n', 'refuse'), ('dims 2 2 2\nbounds 0 0 0 0 1 1\n', 'refuse'),
                ('dims 2 2 2\nbounds 0 0 0 1e999 1 1\n', 'refuse'), ('dims 2,2,2\n', 'refuse'), ('dims 2 2 2\ncolor red\n', 'refuse'),
                ('', 'refuse'), ('dims 2 2 2\x00\n', 'refuse'), ('dims 4294967298 1 2\n', 'refuse'), ('dims 2 2 2\ndims 2 2 2\n', 'refuse'),
                ('dims 0x2 2 2\n', 'refuse'), ('dims 2.0 2 2\n', 'either')]
    for i, (text, e) in enumerate(sidecars):
        grid_file(case, write, 'raw_sidecar_%02d' % i, f32(*([0.5] * 8)), e, 'raw', sidecar=text, note=repr(text))
    okd = df3((2, 2, 2))
    grid_file(case, write, 'df3_ok', okd, 'ok', 'df3')
    for i, (d, body, e) in enumerate([((0, 2, 2), b'', 'refuse'), ((65535, 65535, 65535), b'\0' * 8, 'refuse'), ((2, 2, 2), b'\0' * 7, 'refuse'),
                                      ((2, 2, 2), b'\0' * 9, 'refuse'), ((1, 1, 1), b'\xff', 'ok'), ((2, 2, 2), b'\xff' * 8, 'ok')]):
        grid_file(case, write, 'df3_%02d' % i, df3(d, body), e, 'df3', note='dims %r, %d bytes' % (d, len(body)))
    for cut in (0, 1, 2, 5):
        grid_file(case, write, 'df3_cut_%d' % cut, okd[:cut], 'refuse', 'df3')
    import os
    here = os.path.dirname(os.path.abspath(__file__))
    for fmt in ('nvdb', 'vdb'):
        seed = open(os.path.join(here, 'seeds', 'seed.' + fmt), 'rb').read()
        case('grid_info_%s_ok' % fmt, 'grid', 'ok', ['info', '{C}/seeds/seed.' + fmt])
        for cut in (0, 4, 16, 64, 200, 1000, 4000):
            grid_file(case, write, '%s_cut_%05d' % (fmt, cut), seed[:cut], 'refuse', fmt)
        grid_file(case, write, '%s_text' % fmt, 'not a grid\n', 'refuse', fmt)
    # the same grids rendered: a scene whose medium reads them
    for name, ext, e in [('vol_ok', 'vol', 'image'), ('vol_voxel_07', 'vol', 'refuse'), ('vol_voxel_10', 'vol', 'refuse'),
                         ('vol_dims_05', 'vol', 'refuse'), ('raw_sidecar_01', 'raw', 'image'), ('raw_sidecar_07', 'raw', 'refuse'),
                         ('df3_ok', 'df3', 'image'), ('df3_01', 'df3', 'refuse'), ('nvdb_cut_00200', 'nvdb', 'refuse'),
                         ('vdb_cut_01000', 'vdb', 'refuse'), ('vol_cut_040', 'vol', 'refuse')]:
        s = base()
        s['media'][0]['density'] = {'type': 'grid', 'file': '../grids/%s.%s' % (name, ext)}
        render_scene('grid_render_' + name, 'grid', e, json.dumps(s))
    for dev in ('/dev/zero', '/dev/urandom', '/dev/null', '/proc/self/mem', '/proc/self/fd/0', '/', '.'):
        s = base()
        s['media'][0]['density'] = {'type': 'grid', 'file': dev, 'format': 'raw', 'dims': [2, 2, 2]}
        render_scene('grid_special_%s' % dev.strip('/').replace('/', '_') or 'root', 'grid', 'refuse', json.dumps(s))
        case('grid_info_special_%s' % (dev.strip('/').replace('/', '_') or 'root'), 'grid', 'refuse', ['info', dev])


# ---- meshes --------------------------------------------------------------------------------
OBJ = 'v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n'


def mesh_scene(render_scene, base, name, fname, expect, note=''):
    s = base()
    s['surfaces'] = [{'type': 'mesh', 'file': '../meshes/' + fname}]
    render_scene('mesh_' + name, 'mesh', expect, json.dumps(s), note=note)


def gltf(positions, indices, count=None, uri=None, extra=None):
    pb = f32(*positions)
    ib = struct.pack('<%dH' % len(indices), *indices)
    buf = ib + b'\0' * (len(ib) % 4) + pb
    g = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0}],
         'meshes': [{'primitives': [{'attributes': {'POSITION': 1}, 'indices': 0}]}],
         'buffers': [{'byteLength': len(buf), 'uri': uri or 'data:application/octet-stream;base64,' + base64.b64encode(buf).decode()}],
         'bufferViews': [{'buffer': 0, 'byteOffset': 0, 'byteLength': len(ib)},
                         {'buffer': 0, 'byteOffset': len(ib) + len(ib) % 4, 'byteLength': len(pb)}],
         'accessors': [{'bufferView': 0, 'componentType': 5123, 'count': len(indices), 'type': 'SCALAR'},
                       {'bufferView': 1, 'componentType': 5126, 'count': count or len(positions) // 3, 'type': 'VEC3',
                        'min': [-1, -1, 0], 'max': [1, 1, 0]}]}
    if extra:
        extra(g)
    return json.dumps(g)


def mesh_cases(case, write, render_scene, base):
    write('meshes/ok.obj', OBJ)
    mesh_scene(render_scene, base, 'obj_ok', 'ok.obj', 'image')
    coords = [('nan', 'refuse'), ('inf', 'refuse'), ('-inf', 'refuse'), ('1e999', 'refuse'), ('1e308', 'either'), ('1e19', 'either'),
              ('1e18', 'either'), ('-0', 'image'), ('1e-308', 'image'), ('0x1p3', 'either'), ('abc', 'refuse'), ('', 'refuse')]
    for i, (c, e) in enumerate(coords):
        write('meshes/obj_coord_%02d.obj' % i, OBJ.replace('v 0 1 0', 'v 0 %s 0' % c))
        mesh_scene(render_scene, base, 'obj_coord_%02d' % i, 'obj_coord_%02d.obj' % i, e, note='vertex y = %s' % c)
    faces = [('f 1 2 4', 'refuse'), ('f 0 1 2', 'refuse'), ('f -1 -2 -3', 'image'), ('f -4 1 2', 'refuse'), ('f 1 2', 'refuse'),
             ('f 1 2 99999999999', 'refuse'), ('f 1 2 2147483648', 'refuse'), ('f 1/1/1 2/2/2 3/3/3', 'either'), ('f a b c', 'refuse'),
             ('f 1 2 3 ' + ' '.join(['1'] * 5000), 'refuse'), ('f 1 1 1', 'either')]
    for i, (f, e) in enumerate(faces):
        write('meshes/obj_face_%02d.obj' % i, OBJ.replace('f 1 2 3', f))
        mesh_scene(render_scene, base, 'obj_face_%02d' % i, 'obj_face_%02d.obj' % i, e, note=f[:40])
    for cut in (0, 5, 12, 30):
        write('meshes/obj_cut_%02d.obj' % cut, OBJ[:cut])
        mesh_scene(render_scene, base, 'obj_cut_%02d' % cut, 'obj_cut_%02d.obj' % cut, 'refuse')
    ply = 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n-1 -1 0\n1 -1 0\n0 1 0\n3 0 1 2\n'
    write('meshes/ok.ply', ply)
    mesh_scene(render_scene, base, 'ply_ok', 'ok.ply', 'image')
    plys = [('element vertex 3', 'element vertex 4294967295'), ('element vertex 3', 'element vertex -1'), ('element face 1', 'element face 99999999'),
            ('3 0 1 2', '3 0 1 7'), ('3 0 1 2', '255 0 1 2'), ('0 1 0\n', 'nan 1 0\n'), ('format ascii 1.0', 'format binary_little_endian 1.0'),
            ('format ascii 1.0', 'format ascii 2.0'), ('property float x', 'property floaty x'), ('end_header\n', 'end_header\n\0\0')]
    for i, (a, b) in enumerate(plys):
        write('meshes/ply_%02d.ply' % i, ply.replace(a, b, 1))
        mesh_scene(render_scene, base, 'ply_%02d' % i, 'ply_%02d.ply' % i, 'refuse', note=b[:40])
    for cut in (0, 3, 40, 150, len(ply) - 6):
        write('meshes/ply_cut_%03d.ply' % cut, ply[:cut])
        mesh_scene(render_scene, base, 'ply_cut_%03d' % cut, 'ply_cut_%03d.ply' % cut, 'refuse')
    P, I = [-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, 2]
    write('meshes/ok.gltf', gltf(P, I))
    mesh_scene(render_scene, base, 'gltf_ok', 'ok.gltf', 'image')
    bad = {
        'count_huge': gltf(P, I, count=2 ** 31), 'uri_dev_zero': gltf(P, I, uri='/dev/zero'), 
        'uri_missing': gltf(P, I, uri='nothing.bin'), 'uri_bad_base64': gltf(P, I, uri='data:application/octet-stream;base64,!!!!'),
        'index_out': gltf(P, [0, 1, 9]), 'nan_position': gltf([NAN] + P[1:], I).replace('NaN', '1e999'),
        'byte_length_huge': gltf(P, I, extra=lambda g: g['buffers'][0].update(byteLength=2 ** 40)),
        'view_beyond': gltf(P, I, extra=lambda g: g['bufferViews'][1].update(byteOffset=10 ** 9)),
        'node_cycle': gltf(P, I, extra=lambda g: g['nodes'][0].update(children=[0])),
        'no_meshes': gltf(P, I, extra=lambda g: g.update(meshes=[])), 'not_json': '{"asset": ',
        'version_1': gltf(P, I, extra=lambda g: g['asset'].update(version='1.0')),
    }
    write('meshes/gltf_uri_passwd.gltf', gltf(P, I, uri='../../../../../../etc/passwd'))
    mesh_scene(render_scene, base, 'gltf_uri_passwd', 'gltf_uri_passwd.gltf', 'either')
    for name, text in bad.items():
        write('meshes/gltf_%s.gltf' % name, text)
        mesh_scene(render_scene, base, 'gltf_' + name, 'gltf_%s.gltf' % name, 'refuse')
    for dev in ('/dev/zero', '/dev/urandom', '/'):
        s = base()
        s['surfaces'] = [{'type': 'mesh', 'file': dev}]
        render_scene('mesh_special_%s' % (dev.strip('/').replace('/', '_') or 'root'), 'mesh', 'refuse', json.dumps(s))
    inline = [([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, 2], 'image'), ([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, 3], 'refuse'),
              ([-1, -1, 0, 1, -1, 0, 0, 1], [0, 1, 2], 'refuse'), ([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1], 'refuse'),
              ([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, -1], 'refuse'), ([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, 2.5], 'refuse'),
              ([], [], 'refuse'), ([-1, -1, 0, 1, -1, 0, 0, 1, 0], [0, 1, 2 ** 32], 'refuse'), ([-1, -1, 0, 1, -1, 0, 0, 1e30, 0], [0, 1, 2], 'either')]
    for i, (p, ix, e) in enumerate(inline):
        s = base()
        s['surfaces'] = [{'type': 'mesh', 'positions': p, 'indices': ix}]
        render_scene('mesh_inline_%02d' % i, 'mesh', e, json.dumps(s))
