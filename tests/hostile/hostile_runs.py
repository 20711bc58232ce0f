# hostile_runs.py - the images, checkpoints, command lines, HTTP requests and signals of the
# hostile corpus; called by make_hostile.py, whose header gives the expectations' rules.
import json, struct, zlib

NAN, INF = float('nan'), float('inf')


def pfm(w, h, pixels=None, scale=-1.0, magic='PF', head=None):
    body = struct.pack('<%df' % (w * h * 3), *(pixels or [0.5] * (w * h * 3))) if pixels is not None or w * h < 1e6 else b''
    return (head if head is not None else '%s\n%d %d\n%s\n' % (magic, w, h, scale)).encode() + body


def png_chunk(kind, data, crc=None):
    c = zlib.crc32(kind + data) if crc is None else crc
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', c & 0xffffffff)


def png(w, h, depth=8, color=2, rows=None, interlace=0, crc=None, extra=b'', idat=None):
    channels = {0: 1, 2: 3, 4: 2, 6: 4, 3: 1}.get(color, 3)
    bpp = channels * depth // 8 or 1
    raw = rows if rows is not None else b''.join(b'\0' + b'\x80' * (w * bpp) for _ in range(h))
    ihdr = struct.pack('>IIBBBBB', w, h, depth, color, 0, 0, interlace)
    return (b'\x89PNG\r\n\x1a\n' + png_chunk(b'IHDR', ihdr, crc) + extra +
            png_chunk(b'IDAT', idat if idat is not None else zlib.compress(raw)) + png_chunk(b'IEND', b''))


def exr(w, h, channels, value=lambda c, x, y: 0.5, attrs=None, compression=0, window=None):
    """A scanline OpenEXR file, float channels, uncompressed (compression 0)."""
    names = sorted(channels)
    chl = b''.join(n.encode() + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for n in names) + b'\0'
    win = window or (0, 0, w - 1, h - 1)
    a = [(b'channels', b'chlist', chl), (b'compression', b'compression', bytes([compression])),
         (b'dataWindow', b'box2i', struct.pack('<4i', *win)), (b'displayWindow', b'box2i', struct.pack('<4i', 0, 0, w - 1, h - 1)),
         (b'lineOrder', b'lineOrder', b'\0'), (b'pixelAspectRatio', b'float', struct.pack('<f', 1)),
         (b'screenWindowCenter', b'v2f', struct.pack('<2f', 0, 0)), (b'screenWindowWidth', b'float', struct.pack('<f', 1))]
    a += attrs or []
    head = b'\x76\x2f\x31\x01' + struct.pack('<i', 2) + b''.join(n + b'\0' + t + b'\0' + struct.pack('<i', len(v)) + v for n, t, v in a) + b'\0'
    lines = []
    for y in range(h):
        data = b''.join(struct.pack('<%df' % w, *[value(c, x, y) for x in range(w)]) for c in names)
        lines.append(struct.pack('<ii', y, len(data)) + data)
    offsets, pos = [], len(head) + 8 * h
    for ln in lines:
        offsets.append(pos)
        pos += len(ln)
    return head + struct.pack('<%dQ' % h, *offsets) + b''.join(lines)


PIXELS = [(0.5, 'ok'), (0.0, 'ok'), (-0.0, 'ok'), (1e-45, 'ok'), (1e30, 'ok'), (3e38, 'ok'), (NAN, 'refuse'), (INF, 'refuse'),
          (-INF, 'refuse'), (-1.0, 'refuse'), (-1e-45, 'refuse')]
RGBA = ['A', 'B', 'G', 'R']
DENOISE = RGBA + ['variance.B', 'variance.G', 'variance.R']


def image_cases(case, write, render_scene, base):
    ref = write('images/ref.pfm', pfm(4, 4))
    write('images/ref.exr', exr(4, 4, RGBA))
    case('image_compare_ok', 'image', 'ok', ['compare', ref, ref, '--boot', '0'])
    for i, (v, e) in enumerate(PIXELS):
        p = write('images/pfm_pixel_%02d.pfm' % i, pfm(4, 4, [0.5] * 47 + [v]))
        case('image_compare_pfm_pixel_%02d' % i, 'image', e, ['compare', p, ref, '--boot', '0'], note='pixel %r' % v)
        case('image_compare_pfm_ref_pixel_%02d' % i, 'image', e, ['compare', ref, p, '--boot', '0'], note='reference pixel %r' % v)
        m = write('images/mask_pixel_%02d.pfm' % i, pfm(4, 4, [1.0] * 47 + [v]))
        case('image_compare_mask_pixel_%02d' % i, 'image', e, ['compare', ref, ref, '--boot', '0', '--mask', m], note='mask pixel %r' % v)
        x = write('images/exr_pixel_%02d.exr' % i, exr(4, 4, RGBA, lambda c, x, y, v=v: v if (c, x, y) == ('G', 3, 3) else 0.5))
        case('image_compare_exr_pixel_%02d' % i, 'image', e, ['compare', x, ref, '--boot', '0'], note='pixel %r' % v)
        s = base()
        s['background'] = {'file': '../images/pfm_pixel_%02d.pfm' % i}
        render_scene('image_env_pfm_pixel_%02d' % i, 'image', {'ok': 'image'}.get(e, e), json.dumps(s), note='sky pixel %r' % v)
        d = write('images/denoise_var_%02d.exr' % i, exr(4, 4, DENOISE, lambda c, x, y, v=v: v if (c, x, y) == ('variance.G', 1, 2) else 0.25))
        case('image_denoise_var_%02d' % i, 'image', {'ok': 'image'}.get(e, e), ['denoise', d, '-o', '{T}/out.exr'], note='variance %r' % v)
        d = write('images/denoise_rgb_%02d.exr' % i, exr(4, 4, DENOISE, lambda c, x, y, v=v: v if (c, x, y) == ('R', 0, 0) else 0.25))
        # the beauty layer may be signed (docs/denoise.md: the filter is linear); not NaN or infinite
        er = 'image' if e == 'ok' or v == v and abs(v) != INF else e
        case('image_denoise_rgb_%02d' % i, 'image', er, ['denoise', d, '-o', '{T}/out.png'], note='red %r' % v)
    heads = [('PF\n4 4\n-1\n', 'ok'), ('PF\n4 4\n1\n', 'ok'), ('PF\n4 4\n0\n', 'refuse'), ('PF\n4 4\nnan\n', 'refuse'),
             ('PF\n4 4\n-1e999\n', 'refuse'), ('PF\n-4 4\n-1\n', 'refuse'), ('PF\n0 4\n-1\n', 'refuse'), ('PF\n4 4 4\n-1\n', 'refuse'),
             ('PF\n4\n4\n-1\n', 'either'), ('PF 4 4 -1\n', 'either'), ('Pf\n4 4\n-1\n', 'either'), ('PF\n4294967300 1\n-1\n', 'refuse'),
             ('PF\n65536 65536\n-1\n', 'refuse'), ('PF\n0x4 4\n-1\n', 'refuse'), ('PF\n4 4\n-1', 'refuse'), ('PF\r\n4 4\r\n-1\r\n', 'either')]
    for i, (hd, e) in enumerate(heads):
        n = 48 if 'Pf' not in hd else 16
        p = write('images/pfm_head_%02d.pfm' % i, hd.encode() + struct.pack('<%df' % n, *([0.5] * n)))
        case('image_compare_pfm_head_%02d' % i, 'image', e, ['compare', p, ref, '--boot', '0'], note=repr(hd))
    good = pfm(4, 4)
    for cut in (0, 2, 5, 9, 13, 40, len(good) - 1):
        p = write('images/pfm_cut_%03d.pfm' % cut, good[:cut])
        case('image_compare_pfm_cut_%03d' % cut, 'image', 'refuse', ['compare', p, ref, '--boot', '0'])
    pngs = {'ok': (png(4, 4), 'ok'), 'gray': (png(4, 4, color=0), 'ok'), 'rgba': (png(4, 4, color=6), 'ok'),
            'depth16': (png(4, 4, depth=16), 'ok'), 'interlaced': (png(4, 4, interlace=1, rows=b''.join(b'\0' + b'\x80' * 12 for _ in range(15))), 'either'),
            'bad_crc': (png(4, 4, crc=1), 'refuse'), 'zero_width': (png(0, 4), 'refuse'), 'huge': (png(1000000, 1000000, rows=b''), 'refuse'),
            'palette_no_plte': (png(4, 4, color=3), 'refuse'), 'bad_depth': (png(4, 4, depth=7), 'refuse'), 'bad_color': (png(4, 4, color=5), 'refuse'),
            'idat_garbage': (png(4, 4, idat=b'garbage'), 'refuse'), 'idat_short': (png(4, 4, rows=b'\0\x80'), 'refuse'),
            'bomb': (png(4, 4, rows=b'\0' * 4000000), 'either'), 'text_chunk': (png(4, 4, extra=png_chunk(b'tEXt', b'k\0v')), 'ok'),
            'unknown_critical': (png(4, 4, extra=png_chunk(b'ABCD', b'x')), 'refuse'), 'filter_5': (png(4, 4, rows=b''.join(b'\x05' + b'\x80' * 12 for _ in range(4))), 'refuse')}
    for name, (data, e) in pngs.items():
        p = write('images/png_%s.png' % name, data)
        case('image_compare_png_' + name, 'image', e, ['compare', p, '{C}/images/png_ok.png', '--boot', '0'])
        s = base()
        s['background'] = {'file': '../images/png_%s.png' % name}
        render_scene('image_env_png_' + name, 'image', {'ok': 'image'}.get(e, e), json.dumps(s))
    okx = exr(4, 4, RGBA)
    for cut in (0, 4, 8, 30, 100, 300, len(okx) - 8, len(okx) - 1):
        p = write('images/exr_cut_%04d.exr' % cut, okx[:cut])
        case('image_compare_exr_cut_%04d' % cut, 'image', 'refuse', ['compare', p, ref, '--boot', '0'])
    exrs = {'empty_attr_name': (exr(4, 4, RGBA, attrs=[(b'', b'string', b'x')]), 'refuse'),
            'attr_size_huge': (exr(4, 4, RGBA, attrs=[(b'note', b'string', b'x')]).replace(b'note\0string\0\x01\0\0\0', b'note\0string\0\xff\xff\xff\x7f'), 'refuse'),
            'window_huge': (exr(4, 4, RGBA, window=(0, 0, 2 ** 30, 3)), 'refuse'), 'window_inverted': (exr(4, 4, RGBA, window=(3, 0, 0, 3)), 'refuse'),
            'no_channels': (exr(4, 4, []), 'refuse'), 'compression_99': (exr(4, 4, RGBA, compression=99), 'refuse'),
            'only_red': (exr(4, 4, ['R']), 'either'), 'weird_attr': (exr(4, 4, RGBA, attrs=[(b'\x1b[2J', b'\x07', b'')]), 'either')}
    for name, (data, e) in exrs.items():
        p = write('images/exr_%s.exr' % name, data)
        case('image_compare_exr_' + name, 'image', e, ['compare', p, ref, '--boot', '0'])
        case('image_denoise_exr_' + name, 'image', 'refuse', ['denoise', p, '-o', '{T}/out.exr'])
    case('image_denoise_no_variance', 'image', 'refuse', ['denoise', '{C}/images/ref.exr', '-o', '{T}/out.exr'])
    case('image_denoise_ok', 'image', 'image', ['denoise', '{C}/images/denoise_var_00.exr', '-o', '{T}/out.exr'])
    case('image_denoise_pfm', 'image', 'refuse', ['denoise', ref, '-o', '{T}/out.exr'])
    for dev in ('/dev/zero', '/dev/urandom', '/dev/null', '/'):
        tag = dev.strip('/').replace('/', '_') or 'root'
        case('image_compare_special_' + tag, 'image', 'refuse', ['compare', dev, ref, '--boot', '0'])
        case('image_denoise_special_' + tag, 'image', 'refuse', ['denoise', dev, '-o', '{T}/out.exr'])
        s = base()
        s['background'] = {'file': dev}
        render_scene('image_env_special_' + tag, 'image', 'refuse', json.dumps(s))


# ---- checkpoints: replay.py makes a fresh one with this build, then forges it ----------------
# Layout (src/job/checkpoint.c): header 176 bytes (spp_done at 152, target 156, elapsed 160,
# pixels 168), then n u32[P], active u8[P], sum f64[4P], sq f64[4P], FNV-1a u64 (P = 1 here).
CKPT_SCENE = {"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
              "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1.0}],
              "media": [{"density": {"type": "constant", "value": 1.0}, "sigma_a": 0.1, "sigma_s": 1.0}],
              "render": {"width": 1, "height": 1, "spp": 16777216, "threads": 1}}
P = 1
N_AT, ACTIVE_AT = 176, 176 + 4 * P
SUM_AT = ACTIVE_AT + P
SQ_AT = SUM_AT + 32 * P


def checkpoint_cases(case, write):
    scene = write('checkpoints/scene.json', json.dumps(CKPT_SCENE))
    run = ['render', scene, '-o', '{T}/out.png', '--quiet', '--resume', '{T}/in.ckpt']
    case('ckpt_valid_resume_stops', 'checkpoint', 'stop', run, checkpoint=[], signal='INT', delay=0.5)
    case('ckpt_valid_resume_term', 'checkpoint', 'stop', run, checkpoint=[], signal='TERM', delay=0.5)
    forged = {
        'n_zero': [[N_AT, '<I', 0]], 'n_huge': [[N_AT, '<I', 2 ** 31]], 'n_max': [[N_AT, '<I', 2 ** 32 - 1]],
        'sum_nan': [[SUM_AT, '<d', NAN]], 'sum_inf': [[SUM_AT, '<d', INF]], 'sum_negative': [[SUM_AT, '<d', -1.0]],
        'sum_huge': [[SUM_AT, '<d', 1e308]], 'sq_nan': [[SQ_AT, '<d', NAN]], 'sq_negative': [[SQ_AT, '<d', -1.0]],
        'sq_below_mean': [[SQ_AT, '<d', 0.0], [SUM_AT, '<d', 1.0]], 'alpha_nan': [[SUM_AT + 24, '<d', NAN]],
        'spp_done_negative': [[152, '<i', -1]], 'spp_done_over_target': [[152, '<i', 2 ** 31 - 1]],
        'target_zero': [[156, '<i', 0]], 'elapsed_nan': [[160, '<d', NAN]], 'elapsed_negative': [[160, '<d', -1.0]],
        'pixels_huge': [[168, '<Q', 2 ** 62]], 'pixels_zero': [[168, '<Q', 0]], 'width_two': [[56, '<i', 2]],
        'active_two': [[ACTIVE_AT, '<B', 2]], 'method_unterminated': [[120 + i, '<B', 65] for i in range(32)],
        'format_two': [[8, '<I', 2]], 'order_swapped': [[12, '<I', 0x04030201]], 'build_other': [[16, '<B', 0x30]],
        'scene_key_other': [[48, '<Q', 12345]],
    }
    for name, patches in forged.items():
        case('ckpt_forged_' + name, 'checkpoint', 'refuse', run, checkpoint=patches)
        if name in ('sum_nan', 'n_zero'):
            case('ckpt_forged_%s_term' % name, 'checkpoint', 'refuse', run, checkpoint=patches, signal='TERM', delay=0.3)
    case('ckpt_hash_wrong', 'checkpoint', 'refuse', run, checkpoint=[[SUM_AT, '<d', 0.25]], rehash=False)
    for cut in (0, 7, 8, 100, 176, 180, 200):
        case('ckpt_cut_%03d' % cut, 'checkpoint', 'refuse', run, checkpoint=[], truncate=cut)
    case('ckpt_trailing', 'checkpoint', 'refuse', run, checkpoint=[], append='00')
    for dev in ('/dev/zero', '/dev/null', '/'):
        case('ckpt_special_' + (dev.strip('/').replace('/', '_') or 'root'), 'checkpoint', 'refuse', run[:-1] + [dev])
    case('ckpt_onto_image', 'checkpoint', 'refuse', ['render', scene, '-o', '{T}/out.png', '--quiet', '--checkpoint', '{T}/out.png', '--spp', '4'])
    case('ckpt_onto_scene', 'checkpoint', 'refuse', ['render', '{T}/scene.json', '-o', '{T}/out.png', '--quiet', '--checkpoint', '{T}/scene.json', '--spp', '4'],
         setup={'scene.json': 'checkpoints/scene.json'})
    case('ckpt_onto_notes', 'checkpoint', 'refuse', ['render', scene, '-o', '{T}/out.png', '--quiet', '--checkpoint', '{T}/notes.txt', '--spp', '4'],
         setup={'notes.txt': 'checkpoints/scene.json'})


# ---- command lines ---------------------------------------------------------------------------
FLAG_VALUES = ['0', '-1', '1', '2', '1e3', '0x10', '1,024', ' 4', '4 ', '', 'nan', 'inf', '-0', '99999999999999999999',
               '+4', '4.0', '4.5', '\u0664', '4abc', '2147483648', '-2147483649', '1e-400', '--spp']
# flag: (lo, hi, integer, slow above)
FLAGS = {'--spp': (1, 16777216, True, 64), '--width': (1, 65536, True, 4096), '--height': (1, 65536, True, 4096),
         '--seed': (0, 2 ** 64 - 1, True, None), '--threads': (0, 1024, True, 64), '--max-depth': (1, 100000, True, None),
         '--time': (0.001, 1e9, False, 2), '--min-spp': (1, 16777216, True, 64), '--exposure': (-64, 64, False, None)}


def judge_flag(text, lo, hi, integer, slow):
    t = text
    if integer:
        if t in ('4.0', '-0'):
            return 'either'  # a whole number written as a float, or a signed zero
        if not (t.isascii() and (t.isdigit() or (t[:1] == '-' and t[1:].isdigit()))):
            return 'refuse'
        v = int(t)
    else:
        try:
            if not t.isascii() or t.strip() != t or t.lower() in ('nan', 'inf') or t.startswith(('+', '0x')):
                return 'refuse'
            v = float(t)
        except ValueError:
            return 'refuse'
        if t == '1e-400':
            return 'either'  # underflows to 0
    if v < lo or v > hi:
        return 'refuse'
    if slow is not None and v > slow:
        return 'slow'
    return 'image'


def cli_cases(case, write, base):
    s = base()
    s['render'].pop('threads')
    scene = write('cli/scene.json', json.dumps(s))
    for flag, (lo, hi, integer, slow) in FLAGS.items():
        for i, v in enumerate(FLAG_VALUES):
            e = judge_flag(v, lo, hi, integer, slow)
            case('cli_%s_%02d' % (flag.strip('-').replace('-', '_'), i), 'cli', e, ['render', scene, flag, v, '-o', '{T}/out.png', '--quiet'],
                 note='%s %r' % (flag, v))
        case('cli_%s_missing' % flag.strip('-').replace('-', '_'), 'cli', 'refuse', ['render', scene, '-o', '{T}/out.png', '--quiet', flag])
    sets = [('render.spp=4', 'image'), ('render.spp=1,024', 'refuse'), ('render.spp=4.5', 'refuse'), ('render.spp="4"', 'refuse'),
            ('render.spp=', 'refuse'), ('=4', 'refuse'), ('render..spp=4', 'refuse'), ('media.99.sigma_s=1', 'refuse'),
            ('media.-1.sigma_s=1', 'refuse'), ('media.0.sigma_s=[1,1,1]', 'image'), ('media.0.sigma_s=[1,1', 'refuse'),
            ('media.0.sigma_s=NaN', 'refuse'), ('media.0.sigma_s=1e999', 'refuse'), ('camera=null', 'refuse'), ('camera.fov={"a":1}', 'refuse'),
            ('render.width=8 ', 'either'), ('render.spp=0x4', 'refuse'), ('nokey=1', 'refuse'), ('render.spp=1e400', 'refuse'),
            ('camera.fov=' + '[' * 5000, 'refuse'), ('media.0.density.value=-0', 'image'), ('render.spp=4=5', 'refuse'),
            ('render.spp=01', 'refuse'), ('render.spp=1.', 'refuse'), ('camera.position=[0,0,04]', 'refuse'), ('render.spp=1e0', 'image')]
    for i, (kv, e) in enumerate(sets):
        case('cli_set_%02d' % i, 'cli', e, ['render', scene, '--set', kv, '-o', '{T}/out.png', '--quiet'], note='--set ' + kv[:60])
    victims = {'scene.json': 'cli/scene.json', 'notes.png': 'cli/scene.json', 'notes2-raw.png': 'cli/scene.json', 'ref.pfm': 'images/ref.pfm', 'a.exr': 'images/ref.exr',
               'g.vol': 'grids/vol_ok.vol'}
    outputs = [
        ('onto_scene', ['render', '{T}/scene.json', '-o', '{T}/scene.json', '--quiet']),
        ('onto_notes', ['render', scene, '-o', '{T}/notes.png', '--quiet']),
        ('onto_folder', ['render', scene, '-o', '{T}', '--quiet']),
        ('onto_dev_full', ['render', scene, '-o', '/dev/full', '--quiet']),
        ('checkpoint_onto_dev_full', ['render', scene, '-o', '{T}/out.png', '--checkpoint', '/dev/full', '--quiet']),
        ('onto_dev_null', ['render', scene, '-o', '/dev/null', '--quiet']),
        ('missing_folder', ['render', scene, '-o', '{T}/no/such/folder/out.png', '--quiet']),
        ('unknown_extension', ['render', scene, '-o', '{T}/out.bmp', '--quiet']),
        ('no_extension', ['render', scene, '-o', '{T}/out', '--quiet']),
        ('denoise_raw_onto_notes_raw', ['render', scene, '-o', '{T}/notes2.png', '--denoise', '--quiet']),
        ('denoise_raw_onto_notes', ['render', scene, '-o', '{T}/notes.png', '--denoise', '--quiet']),
        ('save_light_onto_scene', ['render', '{T}/scene.json', '-o', '{T}/out.png', '--method', 'blasi', '--set', 'blasi.light_rays=64', '--save-light', '{T}/scene.json', '--quiet']),
        ('save_light_onto_image', ['render', scene, '-o', '{T}/out.png', '--method', 'blasi', '--set', 'blasi.light_rays=64', '--save-light', '{T}/out.png', '--quiet']),
        ('compare_diff_onto_image', ['compare', '{T}/ref.pfm', '{T}/ref.pfm', '-o', '{T}/ref.pfm', '--boot', '0']),
        ('compare_diff_onto_scene', ['compare', '{T}/ref.pfm', '{T}/ref.pfm', '-o', '{T}/scene.json', '--boot', '0']),
        ('denoise_onto_input', ['denoise', '{T}/a.exr', '-o', '{T}/a.exr']),
        ('convert_onto_source', ['convert', '{T}/g.vol', '{T}/g.vol']),
        ('convert_onto_scene', ['convert', '{T}/g.vol', '{T}/scene.json']),
        ('gen_onto_scene', ['gen', 'cloud', '--dims', '4x4x4', '-o', '{T}/scene.json']),
        ('sweep_onto_scene', ['sweep', '{T}/scene.json', '--set', 'camera.fov=30,40', '-o', '{T}/scene.json']),
        ('render_output_twice', ['render', scene, '-o', '{T}/a.png', '-o', '{T}/b.png', '--quiet']),
    ]
    for name, args in outputs:
        e = 'either' if name in ('missing_folder', 'render_output_twice') else 'refuse'
        case('cli_output_' + name, 'cli', e, args, setup=victims)
    misc = [['paint'], ['render', '--bogus'], ['render', scene, scene], ['help', 'x' * 10000], ['\x1b[2J'], ['render', '-'],
            ['render', scene, '--frames', '0-99999999999', '-o', '{T}/f%04d.png'], ['render', scene, '--frame', '-1', '-o', '{T}/out.png'],
            ['render', scene, '--shard', '0/0', '-o', '{T}/out.png'], ['render', scene, '--device', 'cuda:99', '-o', '{T}/out.png'],
            ['render', scene, '--method', 'stam', '-o', '{T}/out.png'], ['render', scene, '--aov', 'bogus', '-o', '{T}/out.exr'],
            ['render', scene, '--serve', '127.0.0.1:99999', '-o', '{T}/out.png'], ['render', scene, '--serve', 'nohost.invalid:0', '-o', '{T}/out.png'],
            ['render', scene, '--resume', '{T}', '-o', '{T}/out.png'], ['render', scene, '--noise', '2', '-o', '{T}/out.png'],
            ['render', scene, '--up', 'w', '-o', '{T}/out.png'], ['compare', scene, scene], ['gen', 'cloud', '--dims', '100000x100000x100000', '-o', '{T}/c.vol'],
            ['gen', 'fire', '--dims', '0x0x0', '-o', '{T}/c.vol'], ['gen', 'upres', '-o', '{T}/c.vol'], ['info', '{C}/cli/scene.json'],
            ['convert', '{C}/grids/vol_ok.vol', '{T}/x.bmp'], ['sweep', scene, '--set', 'camera.fov=' + ','.join(['30'] * 17), '-o', '{T}/s.png'],
            ['sweep', scene, '--set', 'camera.fov=30,40', '--set', 'render.spp=1,2', '--set', 'render.seed=1,2', '-o', '{T}/s.png'],
            ['slab', '--albedo', 'nan', '--tau', '1', '--phase', 'isotropic'], ['slab', '--albedo', '0.5', '--tau', '1e308', '--phase', 'hg', '--g', '1'],
            ['phase', 'plot', '--bogus'], ['options', '--bogus'], ['devices', '--bogus'], ['figures', '--bogus'], ['render', scene, '--print-scene', '--set', 'x=1']]
    for i, args in enumerate(misc):
        case('cli_misc_%02d' % i, 'cli', 'refuse', args)
    oks = [(['render', scene, '--print-scene'], 'ok'), (['options'], 'ok'), (['help', 'render'], 'ok'), (['--version'], 'ok'),
           (['render', scene, '-o', '{T}/out.pfm', '--quiet'], 'image'), (['render', scene, '-o', '{T}/out.exr', '--aov', 'depth,variance', '--quiet'], 'image'),
           (['render', scene, '-o', '{T}/out.png', '--denoise', '--quiet'], 'image'), (['render', scene, '-o', '{T}/out.png', '--method', 'single', '--quiet'], 'image'),
           (['render', scene, '-o', '{T}/out.png', '--method', 'blasi', '--set', 'blasi.light_rays=64', '--quiet'], 'image'),
           (['render', scene, '-o', '{T}/out.png', '--filmic', '--exposure', '3', '--quiet'], 'image'),
           (['render', scene, '-o', '{T}/out.png', '--set', 'render.spp=2', '--set', 'render.spp=1', '--quiet'], 'image')]
    for i, (args, e) in enumerate(oks):
        case('cli_ok_%02d' % i, 'cli', e, args)


# ---- HTTP requests to --serve ------------------------------------------------------------------
REQUESTS = {
    'get_root': b'GET / HTTP/1.0\r\n\r\n', 'get_status': b'GET /status.json HTTP/1.1\r\nHost: x\r\n\r\n',
    'garbage': b'\x00\x01\x02garbage\r\n\r\n', 'http09': b'GET /\r\n\r\n', 'no_version': b'GET / \r\n\r\n', 'empty_lines': b'\r\n\r\n\r\n',
    'header_no_colon': b'GET / HTTP/1.1\r\nHost x\r\n\r\n', 'long_url': b'GET /' + b'a' * 20000 + b' HTTP/1.1\r\nHost: x\r\n\r\n',
    'long_header': b'GET / HTTP/1.1\r\nHost: x\r\nX-A: ' + b'b' * 20000 + b'\r\n\r\n',
    'many_headers': b'GET / HTTP/1.1\r\nHost: x\r\n' + b''.join(b'X-%d: 1\r\n' % i for i in range(2000)) + b'\r\n',
    'traversal': b'GET /../../../../etc/passwd HTTP/1.1\r\nHost: x\r\n\r\n', 'encoded_traversal': b'GET /%2e%2e/%2e%2e/etc/passwd HTTP/1.1\r\nHost: x\r\n\r\n',
    'nul_in_url': b'GET /image.png%00.html HTTP/1.1\r\nHost: x\r\n\r\n', 'exposure_nan': b'GET /image.png?exposure=nan HTTP/1.1\r\nHost: x\r\n\r\n',
    'exposure_huge': b'GET /image.png?exposure=1e308 HTTP/1.1\r\nHost: x\r\n\r\n', 'exposure_minus': b'GET /image.png?exposure=-1e308 HTTP/1.1\r\nHost: x\r\n\r\n',
    'exposure_twice': b'GET /image.png?exposure=1&exposure=2 HTTP/1.1\r\nHost: x\r\n\r\n', 'query_garbage': b'GET /image.png?%zz=%%% HTTP/1.1\r\nHost: x\r\n\r\n',
    'post_body': b'POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\n\r\nhello', 'post_huge_length': b'POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 99999999999999999999\r\n\r\nx',
    'chunked_bad': b'POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\nhello\r\n0\r\n\r\n',
    'chunked_huge': b'POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\nffffffffffffffff\r\nhello\r\n',
    'put': b'PUT /image.png HTTP/1.1\r\nHost: x\r\nContent-Length: 1\r\n\r\nx', 'delete': b'DELETE / HTTP/1.1\r\nHost: x\r\n\r\n',
    'options': b'OPTIONS * HTTP/1.1\r\nHost: x\r\n\r\n', 'connect': b'CONNECT example.com:443 HTTP/1.1\r\nHost: x\r\n\r\n',
    'head': b'HEAD /image.png HTTP/1.1\r\nHost: x\r\n\r\n', 'range': b'GET /image.png HTTP/1.1\r\nHost: x\r\nRange: bytes=999999999-\r\n\r\n',
    'pipelined': b'GET / HTTP/1.1\r\nHost: x\r\n\r\n' * 50, 'lowercase_method': b'get / HTTP/1.1\r\nHost: x\r\n\r\n',
    'http2_preface': b'PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n', 'tls_hello': bytes.fromhex('16030100a5010000a10303') + b'\0' * 64,
    'partial_never_ends': b'GET / HTTP/1.1\r\nHost: x\r\n', 'only_method': b'GET', 'bare_newlines': b'GET / HTTP/1.1\nHost: x\n\n',
    'stop_get': b'GET /stop HTTP/1.1\r\nHost: x\r\n\r\n', 'stop_with_body': b'POST /stop HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\n\r\nabc',
    'control_chars_url': b'GET /\x1b[2J\x07 HTTP/1.1\r\nHost: x\r\n\r\n', 'utf8_url': 'GET /\u00e9\u6f22 HTTP/1.1\r\nHost: x\r\n\r\n'.encode(),
    'image_never_read': b'GET /image.png HTTP/1.1\r\nHost: x\r\n\r\n',
}


def http_cases(case, write):
    scene = '{C}/cli/scene.json'
    for name, data in REQUESTS.items():
        write('http/%s.bin' % name, data)
        case('http_' + name, 'http', 'serve', ['render', scene, '-o', '{T}/out.png', '--serve', '127.0.0.1:0'], http='http/%s.bin' % name)
    case('http_stop_twice', 'http', 'serve', ['render', scene, '-o', '{T}/out.png', '--serve', '127.0.0.1:0'], http='http/get_root.bin', stops=2)


# ---- signals during a command --------------------------------------------------------------------
def signal_cases(case, write, base):
    s = base()
    s['render'] = {'width': 16, 'height': 16, 'spp': 16777216, 'threads': 2}
    long_scene = write('cli/long.json', json.dumps(s))
    b = base()
    b['render'] = {'width': 8, 'height': 8, 'spp': 1, 'method': 'blasi'}
    b['blasi'] = {'light_rays': 20000000, 'step': 0.0001}  # 6.6e11 units of work: under render.max_work
    b['media'][0]['density'] = {'type': 'procedural_cloud', 'resolution': 64}
    blasi = write('cli/blasi_long.json', json.dumps(b))
    c = base()
    c['media'][0]['sigma_s'] = [10000, 1, 1]  # chromatic, at the colour-channel spread limit
    c['render'] = {'width': 8, 'height': 8, 'spp': 16777216, 'max_depth': 100000}
    chroma = write('cli/chromatic_long.json', json.dumps(c))
    commands = {
        'render': ['render', long_scene, '-o', '{T}/out.png', '--quiet'],
        'chromatic': ['render', chroma, '-o', '{T}/out.png', '--quiet'],
        'render_exr': ['render', long_scene, '-o', '{T}/out.exr', '--aov', 'variance', '--quiet'],
        'render_ckpt': ['render', long_scene, '-o', '{T}/out.png', '--checkpoint', '{T}/c.ckpt', '--quiet'],
        'render_denoise': ['render', long_scene, '-o', '{T}/out.png', '--denoise', '--quiet'],
        'render_time': ['render', long_scene, '-o', '{T}/out.png', '--time', '30', '--quiet'],
        'blasi_light_pass': ['render', blasi, '-o', '{T}/out.png', '--quiet'],
        'gen_cloud': ['gen', 'cloud', '--dims', '256x256x256', '--method', 'spectral', '-o', '{T}/c.vol'],
        'slab': ['slab', '--albedo', '0.99', '--tau', '100', '--phase', 'isotropic', '--samples', '100000000'],
        'sweep': ['sweep', long_scene, '--set', 'camera.fov=30,40', '-o', '{T}/s.png'],
    }
    delays = {'INT': (0.0, 0.2, 0.6, 1.2), 'TERM': (0.1, 0.6), 'HUP': (0.4,)}
    for name, args in commands.items():
        for sig, ds in delays.items():
            for d in ds:
                case('signal_%s_%s_%03d' % (name, sig.lower(), int(d * 100)), 'signal', 'stop', args, signal=sig, delay=d)
    case('signal_render_int_twice', 'signal', 'stop', commands['render'], signal='INT', delay=0.5, repeat=2)
    for d in (0.3, 1.0):  # progress lines on stderr: any number of them
        case('signal_progress_int_%03d' % int(d * 100), 'signal', 'stop', ['render', long_scene, '-o', '{T}/out.png', '--progress-every', '0.1'],
             signal='INT', delay=d, lines='any')


# ---- special files named as inputs: a FIFO (made in the scratch folder), devices, folders ------
SPECIALS = {'fifo': '{T}/fifo', 'dev_zero': '/dev/zero', 'dev_urandom': '/dev/urandom', 'dev_null': '/dev/null', 'folder': '{T}',
            'dev_stdin': '/dev/stdin', 'proc_self_mem': '/proc/self/mem'}


def special_cases(case, write, base):
    s = base()
    s['render']['method'] = 'blasi'
    s['blasi'] = {'light_rays': 64}
    blasi = write('cli/blasi.json', json.dumps(s))
    st = base()
    st['render']['method'] = 'stam'
    st['media'][0]['density'] = {'type': 'blobs', 'blobs': [[0, 0, 0, 1, 0.3]]}
    stam = write('cli/stam.json', json.dumps(st))
    plain = '{C}/cli/scene.json'
    uses = {
        'load_light': [blasi, '--load-light', '%s'], 'load_light_set': [blasi, '--set', 'blasi.load_light="%s"'],
        'kernel_file': [stam, '--set', 'stam.kernel="table"', '--set', 'stam.kernel_file="%s"'],
        'phase_table': [plain, '--set', 'media.0.phase={"type":"tabulated","file":"%s"}'],
        'background': [plain, '--set', 'background={"file":"%s"}'],
        'grid': [plain, '--set', 'media.0.density={"type":"grid","file":"%s","format":"raw","dims":[2,2,2]}'],
        'mesh': [plain, '--set', 'surfaces=[{"type":"mesh","file":"%s"}]'],
        'resume': [plain, '--resume', '%s'], 'scene': ['%s'],
    }
    fifo = {'fifo': ':fifo'}
    for use, args in uses.items():
        for kind, path in SPECIALS.items():
            argv = ['render'] + [a.replace('%s', path) for a in args] + ['-o', '{T}/out.png', '--quiet']
            case('special_%s_%s' % (use, kind), 'special', 'refuse', argv, setup=fifo)
    for kind, path in SPECIALS.items():
        case('special_compare_%s' % kind, 'special', 'refuse', ['compare', path, '{C}/images/ref.pfm', '--boot', '0'], setup=fifo)
        case('special_info_%s' % kind, 'special', 'refuse', ['info', path], setup=fifo)
        case('special_convert_%s' % kind, 'special', 'refuse', ['convert', path, '{T}/x.vol', '--format', 'raw', '--dims', '2x2x2'], setup=fifo)
    sv = base()
    sv['render']['method'] = 'blasi'
    sv['blasi'] = {'light_rays': 64, 'save_light': 'notes.txt'}
    write('cli/save_light_notes.json', json.dumps(sv))
    case('special_save_light_over_notes', 'special', 'refuse', ['render', '{T}/save_light_notes.json', '-o', '{T}/out.png', '--quiet'],
         setup={'save_light_notes.json': 'cli/save_light_notes.json', 'notes.txt': 'cli/scene.json'})
    case('special_save_light_onto_fifo', 'special', 'refuse', ['render', blasi, '--save-light', '{T}/fifo', '-o', '{T}/out.png', '--quiet'], setup=fifo)
    case('special_output_onto_fifo', 'special', 'refuse', ['render', plain, '-o', '{T}/fifo', '--quiet'], setup=fifo)
    case('special_checkpoint_onto_fifo', 'special', 'refuse', ['render', plain, '--checkpoint', '{T}/fifo', '-o', '{T}/out.png', '--quiet'], setup=fifo)
