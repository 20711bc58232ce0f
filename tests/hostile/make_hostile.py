#!/usr/bin/env python3
# make_hostile.py - writes the hostile corpus of tests/hostile/ (its files and MANIFEST.tsv),
# replayed by replay.py (ctest: hostile.corpus). The corpus is committed: the expectations are
# reviewed data. Rerun after editing this file or hostile_files.py:
#     python3 tests/hostile/make_hostile.py
# Every expectation follows from a rule, never from what brume did with the input:
#   refuse  the input breaks a documented range or format: exit non-zero, one line on stderr
#   image   the input is valid: exit 0 and a whole image at the output path
#   ok      a valid input to a command that writes no image (info, compare): exit 0
#   either  a value whose range docs/scene-format.md leaves open (a direction's length, a
#           light's upper bound): refuse or image, never a crash, a hang or several lines
#   stop    a signal during a command: it ends within seconds, by the signal's exit status or
#           0, any image it leaves whole, no temporary file left
#   serve   an HTTP request to --serve: an answer (or a closed connection), the server still
#           serving, then POST /stop ends it with the image written
# Placeholders in a command: {C} this folder, {R} the repository, {T} the case's scratch folder.
import json, os, re, shutil, sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
CASES = []
SLOW = []  # valid but slow (large images, many samples): bench/hostile_slow.sh replays them
NAMES = set()


def case(name, cls, expect, args, **extra):
    assert name not in NAMES, name
    if expect == 'slow':
        expect = 'image'
        dest = SLOW
    else:
        dest = CASES
    assert expect in ('refuse', 'image', 'ok', 'either', 'stop', 'serve'), expect
    NAMES.add(name)
    dest.append((name, cls, expect, args, extra))


def write(rel, data):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'wb' if isinstance(data, bytes) else 'w') as f:
        f.write(data)
    return '{C}/' + rel


OUT = ['-o', '{T}/out.png', '--quiet']


def base():
    return {
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
        "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1.0}],
        "media": [{"density": {"type": "constant", "value": 1.0}, "sigma_a": 0.1, "sigma_s": 1.0}],
        "render": {"width": 8, "height": 8, "spp": 1, "threads": 1},
    }


def render_scene(name, cls, expect, text, ext='json', folder='scenes', extra_args=(), **kw):
    path = write('%s/%s.%s' % (folder, name, ext), text)
    case(name, cls, expect, ['render', path] + OUT + list(extra_args), **kw)


# ---- numbers: every value in a list, judged by the field's documented range ----------------
RAW_TOKENS = ['NaN', 'Infinity', '-Infinity', '1e999', '-1e999', '0x10', '+1', '.5', '1.', '01', '1,5']
NUMBERS = [0, -0.0, 1, -1, 0.5, 2, 1e-308, 5e-324, -5e-324, 1e-30, 1e308, -1e308,
           1.7976931348623157e308, 1e30, -1e30, 1e18, 1e19, 1e12, 1e13, 2 ** 31 - 1, 2 ** 31,
           2 ** 32, 2 ** 53 + 1, 2 ** 63, 2 ** 64, -2 ** 63, 65536, 65537, 16777216, 16777217,
           179, 179.0001, 0.001, 0.00099, 100000, 100001, 90, 90.0001, 1024, 1025, 1.5, 1e9, 1e-9]
WRONG_TYPES = ['1', 'nan', '', None, True, False, [], {}, [1, 2, 3], {"value": 1}]


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool) or (isinstance(v, float) and v == int(v) and abs(v) < 2 ** 63)


def rng(lo, hi, lo_open=False, hi_open=False, integer=False, either_above=None, either_below=None):
    """A judge: value -> 'image', 'refuse' or 'either' for a number in [lo, hi] (or open)."""
    def judge(v):
        if integer and not is_int(v):
            return 'refuse'
        if v < lo or v > hi or (lo_open and v == lo) or (hi_open and v == hi):
            return 'refuse'
        if either_above is not None and abs(v) > either_above:
            return 'either'
        if either_below is not None and v != 0 and abs(v) < either_below:
            return 'either'
        return 'image'
    return judge


def also(judge, bad):
    """judge, except the values bad(v) are refused."""
    return lambda v: 'refuse' if bad(v) else judge(v)


def set_path(s, path, value, label=None):
    if path[:2] == ['camera', 'up']:
        s['camera'].setdefault('up', [0, 1, 0])
    if label in PREP:
        set_path(s, *PREP[label])
    o = s
    for k in path[:-1]:
        o = o[k]
    o[path[-1]] = value


# (label, path in the scene, judge, base scene changes); slow-but-valid values are left to
# bench/hostile_slow.sh: the judge returns 'slow' for them.
def slow_above(judge, limit):
    return lambda v: 'slow' if judge(v) == 'image' and v > limit else judge(v)


FIELDS = [
    ('fov', ['camera', 'fov'], rng(0.001, 179)),
    ('pos_x', ['camera', 'position', 0], rng(-1e18, 1e18)),
    ('pos_z', ['camera', 'position', 2], also(rng(-1e18, 1e18, either_below=1e-30), lambda v: v == 0)),
    ('look_x', ['camera', 'look_at', 0], rng(-1e30, 1e30)),
    ('up_y', ['camera', 'up', 1], also(rng(-1e30, 1e30, either_below=1e-30), lambda v: v == 0)),
    ('aperture', ['camera', 'aperture_radius'], rng(0, 1e18, either_above=1e17)),
    ('focus', ['camera', 'focus_distance'], rng(1e-9, 1e30)),
    ('irradiance', ['lights', 0, 'irradiance'], rng(0, float('inf'), either_above=1e12)),
    ('sun_radius', ['lights', 0, 'angular_radius'], also(rng(0, 90, either_above=89.99), lambda v: v > 90)),
    ('light_dir_y', ['lights', 0, 'direction', 1], also(rng(-1e308, 1e308, either_above=1e30, either_below=1e-30), lambda v: v == 0)),
    ('sigma_a', ['media', 0, 'sigma_a'], rng(0, 1e12, either_above=1e11)),
    ('sigma_s', ['media', 0, 'sigma_s'], rng(0, 1e12, either_above=1e11)),
    ('density', ['media', 0, 'density', 'value'], rng(0, 1e30, either_above=1e11)),
    ('width', ['render', 'width'], slow_above(rng(1, 65536, integer=True), 4096)),
    ('height', ['render', 'height'], slow_above(rng(1, 65536, integer=True), 4096)),
    ('spp', ['render', 'spp'], slow_above(rng(1, 16777216, integer=True), 64)),
    ('seed', ['render', 'seed'], rng(0, 2 ** 64 - 1, integer=True, either_above=2 ** 53)),
    ('threads', ['render', 'threads'], slow_above(rng(0, 1024, integer=True), 64)),
    ('max_depth', ['render', 'max_depth'], rng(1, 100000, integer=True)),
    ('fps', ['render', 'fps'], rng(1e-6, 1e6)),
    # a budget shorter than the first sample is refused (never a 0-sample image): below 0.1 s either
    ('time_budget', ['render', 'time'], slow_above(rng(0, 1e9, either_below=0.1), 2)),
    ('max_memory', ['render', 'max_memory_mb'], rng(1, 1e9)),
    ('max_work', ['render', 'max_work'], rng(1, 1e18)),
    ('sun_lobe', ['path', 'sun_lobe'], rng(0, 100)),
    ('sun_roulette', ['path', 'sun_roulette'], rng(0, 1)),
    ('split', ['path', 'split'], rng(1, 8, integer=True)),
    # a chromatic medium: one channel extreme, the others 1 (the colour-channel spread limit: either above 1e4)
    ('sigma_s_red', ['media', 0, 'sigma_s', 0], rng(0, 1e12, either_above=1e4)),
    ('sigma_a_blue', ['media', 0, 'sigma_a', 2], rng(0, 1e12, either_above=1e4)),
    ('irradiance_green', ['lights', 0, 'irradiance', 1], rng(0, float('inf'), either_above=1e12)),
    ('background_red', ['background', 0], rng(0, float('inf'), either_above=1e12)),
]
PREP = {'sigma_s_red': (['media', 0, 'sigma_s'], [1, 1, 1]), 'sigma_a_blue': (['media', 0, 'sigma_a'], [0.1, 0.1, 0.1]),
        'irradiance_green': (['lights', 0, 'irradiance'], [1, 1, 1]), 'background_red': (['background'], [0.1, 0.1, 0.1])}


def field_cases():
    for label, path, judge in FIELDS:
        for i, v in enumerate(NUMBERS):
            expect = judge(v)
            s = base()
            if path[0] == 'path':
                s['path'] = {}
            set_path(s, path, v, label)
            render_scene('num_%s_%02d' % (label, i), 'scene', expect, json.dumps(s), note='%s = %r' % ('.'.join(map(str, path)), v))
        for i, v in enumerate(WRONG_TYPES):
            s = base()
            if path[0] == 'path':
                s['path'] = {}
            set_path(s, path, v, label)
            color = label in ('irradiance', 'sigma_a', 'sigma_s') and v == [1, 2, 3]  # a colour: valid
            render_scene('type_%s_%02d' % (label, i), 'scene', 'image' if color else 'refuse', json.dumps(s),
                         note='%s = %r' % ('.'.join(map(str, path)), v))
        for i, tok in enumerate(RAW_TOKENS):
            s = base()
            if path[0] == 'path':
                s['path'] = {}
            set_path(s, path, '@@TOKEN@@', label)
            text = json.dumps(s).replace('"@@TOKEN@@"', tok)
            render_scene('token_%s_%02d' % (label, i), 'scene', 'refuse', text, note='%s = %s (not JSON)' % ('.'.join(map(str, path)), tok))


# ---- structure: the scene's objects replaced, nested, repeated ------------------------------
def structure_cases():
    b = json.dumps(base())
    for key in ('camera', 'lights', 'media', 'render'):
        for i, v in enumerate(WRONG_TYPES):
            if (key in ('lights', 'media') and v == []) or (key == 'render' and v == {}):
                continue  # no lights, no media, render's defaults: valid scenes (below)
            s = base()
            s[key] = v
            render_scene('object_%s_%02d' % (key, i), 'scene', 'refuse', json.dumps(s), note='%s = %r' % (key, v))
    texts = {
        'dup_key_top': b[:-1] + ', "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]}}',
        'dup_key_render': b.replace('"threads": 1', '"threads": 1, "threads": 2'),
        'deep_array_10000': '[' * 10000 + ']' * 10000,
        'deep_object_5000': '{"a":' * 5000 + '1' + '}' * 5000,
        'deep_in_comment': b[:-1] + ', "comment": ' + '[' * 3000 + ']' * 3000 + '}',
        'trailing_comma': b[:-1] + ',}',
        'trailing_garbage': b + 'x',
        'two_objects': b + b,
        'utf16': b.encode('utf-16'),
        'invalid_utf8_key': b[:-1].encode() + b', "\xff\xfe": 1}',
        'nul_in_string': b.replace('"threads"', '"thr\\u0000eads"'),
        'lone_surrogate': b.replace('"threads"', '"\\ud800"'),
        'comment_c_style': '/* hi */' + b,
        'single_quotes': b.replace('"', "'"),
        'empty_object': '{}',
        'null_document': 'null',
        'number_document': '1',
        'string_document': '"scene"',
        'whitespace_only': '   \n\t  ',
        'key_control_chars': b[:-1] + ', "\\u001b[2J\\u0007": 1}',
        'media_17': json.dumps(dict(base(), media=base()['media'] * 17)),
    }
    for name, text in texts.items():
        render_scene('struct_' + name, 'scene', 'refuse', text)
    ok = {
        'no_lights': dict(base(), lights=[]),
        'no_media': dict(base(), media=[]),
        'comment_everywhere': dict(base(), comment='x', camera=dict(base()['camera'], comment=[1, {"a": None}])),
        'lights_64': dict(base(), lights=base()['lights'] * 64),
        'media_16': dict(base(), media=base()['media'] * 16),
        'long_comment': dict(base(), comment='x' * 20000),
    }
    for name, s in ok.items():
        render_scene('struct_' + name, 'scene', 'image', json.dumps(s))
    render_scene('struct_render_defaults', 'scene', 'slow', json.dumps(dict(base(), render={})))  # 640 x 480, 16 spp


def truncation_cases():
    """Every scene of scenes/ cut at a spread of offsets before its closing brace: never JSON."""
    for fn in sorted(os.listdir(os.path.join(REPO, 'scenes'))):
        if not fn.endswith('.json'):
            continue
        text = open(os.path.join(REPO, 'scenes', fn), encoding='utf-8').read()
        end = text.rstrip().rfind('}')
        cuts = sorted(set([0, 1, end] + [end * k // 9 for k in range(1, 9)]))
        for c in cuts:
            cut = text[:c]
            if len(cut) > 4096:  # keep the corpus small: the head and the tail of a long file
                cut = cut[:2048]
            render_scene('trunc_%s_%05d' % (fn[:-5].replace('-', '_'), c), 'scene', 'refuse', cut, folder='truncated')


# Known defects: cases that fail today, with the reason. replay.py lists them
# apart while they fail and fails once one passes, so that its mark is removed here.
KNOWN = {}


def main():
    for d in ('scenes', 'truncated', 'pbrt', 'grids', 'meshes', 'images', 'checkpoints', 'http', 'cli'):
        shutil.rmtree(os.path.join(HERE, d), ignore_errors=True)
    field_cases()
    structure_cases()
    truncation_cases()
    import hostile_files, hostile_runs
    hostile_files.pbrt_cases(render_scene)
    hostile_files.grid_cases(case, write, render_scene, base)
    hostile_files.mesh_cases(case, write, render_scene, base)
    hostile_runs.image_cases(case, write, render_scene, base)
    hostile_runs.checkpoint_cases(case, write)
    hostile_runs.cli_cases(case, write, base)
    hostile_runs.http_cases(case, write)
    hostile_runs.signal_cases(case, write, base)
    hostile_runs.special_cases(case, write, base)
    for name, cls, expect, args, extra in CASES:
        for pattern, reason in KNOWN.items():
            if re.fullmatch(pattern, name):
                extra['known'] = reason
    for fn, cases, what in (('MANIFEST.tsv', CASES, 'replay.py (ctest hostile.corpus)'), ('SLOW.tsv', SLOW, 'bench/hostile_slow.sh')):
        with open(os.path.join(HERE, fn), 'w') as f:
            f.write('# %s - written by make_hostile.py (edit that, then rerun it); replayed by %s.\n' % (fn, what))
            f.write('# case\tclass\texpect\targs (JSON)\textra (JSON: signal, delay, http, setup, checkpoint, note)\n')
            for name, cls, expect, args, extra in cases:
                f.write('%s\t%s\t%s\t%s\t%s\n' % (name, cls, expect, json.dumps(args), json.dumps(extra, sort_keys=True)))
    counts = {}
    for c in CASES:
        counts[c[1]] = counts.get(c[1], 0) + 1
    print('%d cases (%d slow ones apart): %s' % (len(CASES), len(SLOW), ', '.join('%s %d' % kv for kv in sorted(counts.items()))))


if __name__ == '__main__':
    main()
