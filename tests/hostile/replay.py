#!/usr/bin/env python3
"""replay.py - replays the hostile corpus (MANIFEST.tsv, written by make_hostile.py) against the
brume tool and checks each case's expected outcome (make_hostile.py's header gives the rules).

Usage: replay.py BRUME [--jobs N] [--only REGEX] [--sanitized] [--time-scale F] [--manifest TSV]
Each case runs in a scratch folder of its own (its working directory, HOME and TMPDIR), under
limits set in the child: CPU time (RLIMIT_CPU), address space (RLIMIT_AS, off with --sanitized:
the sanitizers' shadow memory needs more), file size (RLIMIT_FSIZE) and a wall-clock limit. A
case fails when brume dies of a signal it was not sent, runs past a limit, prints a sanitizer
report, answers a refusal with other than one line, writes a file outside its scratch folder
(the corpus and the repository's scenes/ are checked before and after the run) or changes a
file it was given (a copy of an input placed in the scratch folder). Every failing case is
named with its reason; exit 1 if any failed. A case marked as a known defect (make_hostile.py's
KNOWN, each with its reason and owner) is listed apart while it fails, and fails once it passes. Runs the cases in parallel (--jobs, default the
number of cores). stdlib only."""
import argparse, concurrent.futures as futures, hashlib, json, os, re, resource, shutil, signal, socket
import struct, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SANITIZER = re.compile(rb'(AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|runtime error:|ThreadSanitizer)')
SIGNALS = {'INT': signal.SIGINT, 'TERM': signal.SIGTERM, 'HUP': signal.SIGHUP}
OPT = None


def limits(as_limit):
    def apply():
        os.setsid()
        resource.setrlimit(resource.RLIMIT_CPU, (int(20 * OPT.time_scale), int(20 * OPT.time_scale) + 5))
        resource.setrlimit(resource.RLIMIT_FSIZE, (256 << 20, 256 << 20))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if as_limit:
            resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    return apply


def image_ok(path):
    """'' when path holds a whole PNG, PFM or EXR image (or .vol grid), else why not."""
    try:
        data = open(path, 'rb').read()
    except OSError as e:
        return 'no image (%s)' % e.strerror
    if data.startswith(b'\x89PNG\r\n\x1a\n'):
        w, h = struct.unpack('>II', data[16:24])
        return '' if w > 0 and h > 0 and data.endswith(b'IEND\xaeB`\x82') else 'PNG not whole'
    if data.startswith(b'\x76\x2f\x31\x01'):
        return '' if len(data) > 100 else 'EXR too short'
    if data.startswith(b'VOL\x03') and len(data) >= 48:  # a grid (gen cloud): Mitsuba's float volume
        nx, ny, nz, ch = struct.unpack('<4i', data[8:24])
        return '' if len(data) == 48 + nx * ny * nz * ch * 4 else 'VOL not whole'
    m = re.match(rb'P[Ff]\s+(\d+)\s+(\d+)\s+(\S+)\s', data)
    if m:
        n = int(m.group(1)) * int(m.group(2)) * (3 if data[1:2] == b'F' else 1) * 4
        return '' if len(data) - m.end() == n else 'PFM not whole'
    return 'not an image'


def snapshot(folder):
    out = {}
    for root, dirs, files in os.walk(folder):
        for f in files:
            p = os.path.join(root, f)
            try:
                st = os.lstat(p)
                out[p] = (st.st_size, st.st_mtime_ns)
            except OSError:
                pass
    return out


def digest(path):
    with open(path, 'rb') as f:
        return hashlib.sha1(f.read()).hexdigest()


def fill(arg, scratch):
    return arg.replace('{C}', HERE).replace('{R}', REPO).replace('{T}', scratch)


def forge_checkpoint(dst, extra):
    data = bytearray(open(os.path.join(OPT.work, 'fresh.ckpt'), 'rb').read())
    for off, fmt, value in extra['checkpoint']:
        struct.pack_into(fmt, data, off, value)
    if extra.get('rehash', True) and extra['checkpoint']:
        h = 0xcbf29ce484222325
        for b in data[:-8]:
            h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
        struct.pack_into('<Q', data, len(data) - 8, h)
    if 'truncate' in extra:
        data = data[:extra['truncate']]
    data += bytes.fromhex(extra.get('append', ''))
    open(dst, 'wb').write(data)


def make_checkpoint():
    """A checkpoint of corpus/checkpoints/scene.json written by this build: stopped after 1 s."""
    dst = os.path.join(OPT.work, 'fresh.ckpt')
    scene = os.path.join(HERE, 'checkpoints', 'scene.json')
    for wait in (1.0, 2.0, 4.0):
        p = subprocess.Popen([OPT.brume, 'render', scene, '-o', os.path.join(OPT.work, 'ck.png'), '--quiet', '--checkpoint', dst],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(wait * OPT.time_scale)
        p.send_signal(signal.SIGINT)
        p.wait()
        if os.path.exists(dst):
            return True
    return False


def read_port(err_path, proc, deadline):
    while time.time() < deadline and proc.poll() is None:
        try:
            m = re.search(rb'http://127\.0\.0\.1:(\d+)/', open(err_path, 'rb').read())
            if m:
                return int(m.group(1))
        except OSError:
            pass
        time.sleep(0.05)
    return 0


def http(port, data, timeout=5.0, read=True):
    s = socket.create_connection(('127.0.0.1', port), timeout=timeout)
    try:
        s.sendall(data)
        if not read:
            return s
        s.shutdown(socket.SHUT_WR)
        got = b''
        while True:
            chunk = s.recv(65536)
            if not chunk:
                break
            got += chunk
        return got
    finally:
        if read:
            s.close()


def drive_serve(proc, err_path, extra):
    """Sends the case's request, checks the server still answers, stops it; '' or why not."""
    port = read_port(err_path, proc, time.time() + 15 * OPT.time_scale)
    if not port:
        return 'no "live view at" port on stderr'
    deadline = time.time() + 15 * OPT.time_scale  # the render done: a stop keeps its image
    while b'serving the final image' not in open(err_path, 'rb').read():
        if time.time() > deadline or proc.poll() is not None:
            return 'the render did not finish'
        time.sleep(0.05)
    req = open(os.path.join(HERE, extra['http']), 'rb').read()
    held = None
    try:
        if extra['http'].endswith('image_never_read.bin') or extra['http'].endswith('partial_never_ends.bin'):
            held = http(port, req, read=False)
        else:
            got = http(port, req)
            if got and not got.startswith(b'HTTP/1.'):
                return 'answer is not HTTP: %r' % got[:40]
    except socket.timeout:
        return 'no answer within 5 s'
    except OSError:
        pass  # the server may close a connection it refuses
    if 'stop' in extra['http']:
        time.sleep(0.5)  # a stop it took: the server is going
    try:
        st = b'HTTP/1.0 200' if proc.poll() is not None else http(port, b'GET /status.json HTTP/1.0\r\n\r\n')
        if not st.startswith(b'HTTP/1.1 200') and not st.startswith(b'HTTP/1.0 200'):
            return 'status.json after the request: %r' % st[:40]
        for i in range(extra.get('stops', 1)):
            if proc.poll() is not None:
                break  # the request itself was a stop
            try:
                http(port, b'POST /stop HTTP/1.0\r\n\r\n')
            except OSError:
                if i == 0:
                    raise
                break  # the first stop ended it before the next could connect
    except OSError as e:
        return 'server gone after the request (%s)' % e
    finally:
        if held:
            held.close()
    return ''


def run_case(c):
    name, cls, expect, args, extra = c
    scratch = tempfile.mkdtemp(prefix=name[:40] + '.', dir=OPT.work)
    os.makedirs(os.path.join(scratch, 'tmp'))
    try:
        return name, check_case(name, expect, args, extra, scratch)
    except Exception as e:  # a defect of this script, reported as the case's failure
        return name, 'replay error: %r' % e
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def check_case(name, expect, args, extra, scratch):
    for dst, src in extra.get('setup', {}).items():
        if src == ':fifo':
            os.mkfifo(os.path.join(scratch, dst))
        else:
            shutil.copy(os.path.join(HERE, src), os.path.join(scratch, dst))
    if 'checkpoint' in extra:
        forge_checkpoint(os.path.join(scratch, 'in.ckpt'), extra)
    present = set(os.listdir(scratch))
    given = {f: digest(os.path.join(scratch, f)) for f in present if os.path.isfile(os.path.join(scratch, f))}
    argv = [OPT.brume] + [fill(a, scratch) for a in args]
    err_path = os.path.join(scratch, 'tmp', 'stderr')
    env = dict(os.environ, HOME=scratch, TMPDIR=os.path.join(scratch, 'tmp'), LC_ALL='C')
    wall = (30.0 if expect in ('stop', 'serve') else 20.0) * OPT.time_scale
    t0 = time.time()
    with open(err_path, 'wb') as err:
        proc = subprocess.Popen(argv, cwd=scratch, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err,
                                preexec_fn=limits(not OPT.sanitized))
        why, sent, sent_at = '', None, None
        if expect == 'serve':
            why = drive_serve(proc, err_path, extra)
        elif 'signal' in extra:
            time.sleep(extra['delay'] * OPT.time_scale)
            sent, sent_at = SIGNALS[extra['signal']], time.time()
            for k in range(extra.get('repeat', 1)):
                if proc.poll() is None:
                    proc.send_signal(sent)
                    time.sleep(0.1)
            wall = 5.0 * OPT.time_scale + (time.time() - t0)
        try:
            rc = proc.wait(timeout=max(0.1, wall - (time.time() - t0)))
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            late = ' after the signal' if sent else ''
            return (why + '; ' if why else '') + 'still running %.0f s%s (limit)' % (time.time() - (sent_at or t0), late)
        finally:
            try:
                os.killpg(proc.pid, signal.SIGKILL)  # a child it left behind
            except OSError:
                pass
    if why:
        return why
    stderr = open(err_path, 'rb').read()
    if SANITIZER.search(stderr):
        return 'sanitizer report: ' + stderr.decode(errors='replace').strip().splitlines()[0][:200]
    for f, h in given.items():
        p = os.path.join(scratch, f)
        out_arg = fill('{T}/' + f, scratch)
        if not os.path.exists(p):
            return 'input %s removed' % f
        if digest(p) != h and not (expect in ('image', 'either') and out_arg in argv and argv[argv.index(out_arg) - 1] == '-o' and f.endswith(('.png', '.exr', '.pfm')) and given_is_image(p)):
            return 'input %s changed' % f
    return judge(expect, rc, stderr, argv, scratch, sent, extra, present)


def given_is_image(p):
    return image_ok(p) == ''


def outputs(argv):
    """The output path: the last -o wins."""
    return [argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ('-o', '--output')][-1:]


def judge(expect, rc, stderr, argv, scratch, sent, extra, given):
    lines = stderr.decode(errors='replace').splitlines()
    one_line = len(lines) == 1 and stderr.endswith(b'\n') and lines[0].strip() != ''
    desc = 'exit %s' % (('signal %s' % signal.Signals(-rc).name) if rc < 0 else rc)
    first = (' "%s"' % lines[0][:160]) if lines else ''
    if rc < 0 and not (sent and -rc == sent):
        return 'killed by %s%s' % (signal.Signals(-rc).name, first)
    outs = [o for o in outputs(argv) if not os.path.isdir(o)]
    leftovers = [f for f in os.listdir(scratch) if f not in given and f != 'tmp' and not any(o.endswith('/' + f) for o in outs)
                 and not f.endswith(('.ckpt', '-raw.png', '.exr', '.png'))]
    if expect == 'refuse' or (expect == 'either' and rc != 0):
        if rc == 0:
            return 'exit 0, a refusal expected'
        if not one_line:
            return '%s with %d lines on stderr%s' % (desc, len(lines), first)
        made = [o for o in outs if o.startswith(scratch) and os.path.basename(o) not in given and os.path.exists(o)]
        return 'refused but wrote %s' % made[0] if made else ''
    if expect in ('image', 'ok', 'either', 'serve'):
        if rc != 0 and not (expect == 'serve' and rc == 130):  # stopped while rendering: the image so far
            return '%s%s, %s expected' % (desc, first, 'an image' if expect != 'ok' else 'success')
        if expect != 'ok':
            for o in outs:
                bad = image_ok(o)
                if bad:
                    return 'exit 0 but %s: %s' % (os.path.basename(o), bad)
        return ''
    # stop: ends by the signal's status (or 0: finished first), any image whole, nothing half-written
    if rc not in (0, 128 + sent) and rc != -sent:
        return '%s after SIG%s%s' % (desc, signal.Signals(sent).name[3:], first)
    if len(lines) > 2 and extra.get('lines') != 'any':
        return '%s with %d lines on stderr%s' % (desc, len(lines), first)
    for o in outs:
        if os.path.exists(o) and image_ok(o):
            return '%s: %s' % (os.path.basename(o), image_ok(o))
    temps = [f for f in os.listdir(scratch) if '.tmp' in f or f.startswith('.')]
    return 'temporary files left: %s' % temps[:3] if temps else ''


def main():
    global OPT
    ap = argparse.ArgumentParser()
    ap.add_argument('brume')
    ap.add_argument('--jobs', type=int, default=os.cpu_count() or 2)
    ap.add_argument('--only', default='')
    ap.add_argument('--sanitized', action='store_true')
    ap.add_argument('--time-scale', type=float, default=1.0)
    ap.add_argument('--every', type=int, default=1, help='replay every N-th case of each class (N >= 1)')
    ap.add_argument('--manifest', default=os.path.join(HERE, 'MANIFEST.tsv'))
    OPT = ap.parse_args()
    OPT.brume = os.path.abspath(OPT.brume)
    cases = []
    for line in open(OPT.manifest, encoding='utf-8'):
        if line.startswith('#') or not line.strip():
            continue
        name, cls, expect, args, extra = line.rstrip('\n').split('\t')
        if OPT.only and not re.search(OPT.only, name):
            continue
        cases.append((name, cls, expect, json.loads(args), json.loads(extra)))
    if OPT.every > 1:  # a deterministic sample that keeps every class
        seen = {}
        kept = []
        for c in cases:
            seen[c[1]] = seen.get(c[1], -1) + 1
            if seen[c[1]] % OPT.every == 0:
                kept.append(c)
        cases = kept
    marks = {c[0]: c[4]['known'] for c in cases if 'known' in c[4]}
    OPT.work = tempfile.mkdtemp(prefix='brume-hostile.')
    watched = [HERE, os.path.join(REPO, 'scenes')]
    before = [snapshot(w) for w in watched]
    t0 = time.time()
    fails, known = [], []
    try:
        if any('checkpoint' in c[4] for c in cases) and not make_checkpoint():
            fails.append(('checkpoints', 'could not make a checkpoint to forge'))
        order = sorted(cases, key=lambda c: c[2] not in ('stop', 'serve'))  # the slow ones first
        with futures.ThreadPoolExecutor(OPT.jobs) as pool:
            for name, why in pool.map(run_case, order):
                mark = marks.get(name)
                if why and mark:
                    known.append((name, why, mark))
                elif why:
                    fails.append((name, why))
                elif mark:
                    fails.append((name, 'passes now: remove its known-defect mark in make_hostile.py (%s)' % mark))
    finally:
        shutil.rmtree(OPT.work, ignore_errors=True)
    for w, b in zip(watched, before):
        a = snapshot(w)
        for p in sorted(set(a) ^ set(b)) + [p for p in a if p in b and a[p] != b[p]]:
            fails.append(('corpus', '%s %s during the run' % (p, 'appeared or vanished' if (p in a) != (p in b) else 'changed')))
    by_class = {}
    for c in cases:
        by_class.setdefault(c[1], [0, 0])[0] += 1
    failed = {n for n, _ in fails}
    for c in cases:
        if c[0] in failed:
            by_class[c[1]][1] += 1
    for name, why, mark in sorted(known):
        print('KNOWN %s: %s [%s]' % (name, why, mark))
    for name, why in sorted(fails):
        print('FAIL %s: %s' % (name, why))
    print('hostile corpus: %d cases, %d failed, %d known defects, %.1f s (%s)' % (len(cases), len(fails), len(known), time.time() - t0,
          ', '.join('%s %d/%d' % (k, v[0] - v[1], v[0]) for k, v in sorted(by_class.items()))))
    return 1 if fails else 0


if __name__ == '__main__':
    sys.exit(main())
