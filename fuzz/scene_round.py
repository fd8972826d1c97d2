#!/usr/bin/env python3
"""Structured hostile scenes against the pointillist binary: valid skeletons with random
states, extreme floats, random FVFs and vertices, inline textures, emitters, viewports,
plus single-key corruptions. Checks: exit 0 with a PNG, or exit 1 with one printable line
and no output; never a signal, panic, timeout, leftover temporary file. Error lines are
appended to errors.txt in the work folder, to read for unclear messages.

Usage: python3 fuzz/scene_round.py target/release/pointillist COUNT SEED"""
import glob, os, random, subprocess, sys, time

BIN, N, SEED = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rng = random.Random(SEED)
WORK = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"pointillist-round-{SEED}")
os.makedirs(WORK, exist_ok=True)

FLOATS = ["0.0", "-0.0", "1.0", "0.5", "64.0", "8192.0", "1e38", "-1e38", "1e-45", "1e-38",
          "inf", "-inf", "nan", "3.4028235e38", "-1.0", "0.001", "2.5", "100.0", "16384.0"]
def f(): return rng.choice(FLOATS) if rng.random() < 0.3 else repr(rng.uniform(-300, 300))
BLENDS = ["ZERO", "ONE", "SRCCOLOR", "INVSRCCOLOR", "SRCALPHA", "INVSRCALPHA", "DESTALPHA",
          "INVDESTALPHA", "DESTCOLOR", "INVDESTCOLOR", "SRCALPHASAT", "BLENDFACTOR", "INVBLENDFACTOR"]
CMPS = ["NEVER", "LESS", "EQUAL", "LESSEQUAL", "GREATER", "NOTEQUAL", "GREATEREQUAL", "ALWAYS"]
STATES = {
    "POINTSIZE": f, "POINTSIZE_MIN": f, "POINTSIZE_MAX": f, "POINTSCALE_A": f,
    "POINTSCALE_B": f, "POINTSCALE_C": f,
    "POINTSPRITEENABLE": lambda: rng.choice(["true", "false"]),
    "POINTSCALEENABLE": lambda: rng.choice(["true", "false"]),
    "ALPHABLENDENABLE": lambda: rng.choice(["true", "false"]),
    "ZENABLE": lambda: rng.choice(["true", "false"]),
    "ZWRITEENABLE": lambda: rng.choice(["true", "false"]),
    "ALPHATESTENABLE": lambda: rng.choice(["true", "false"]),
    "FOGENABLE": lambda: rng.choice(["true", "false"]),
    "LIGHTING": lambda: rng.choice(["true", "false"]),
    "SRCBLEND": lambda: f'"{rng.choice(BLENDS)}"', "DESTBLEND": lambda: f'"{rng.choice(BLENDS)}"',
    "ZFUNC": lambda: f'"{rng.choice(CMPS)}"', "ALPHAFUNC": lambda: f'"{rng.choice(CMPS)}"',
    "ALPHAREF": lambda: str(rng.randrange(0, 256)),
    "COLORWRITEENABLE": lambda: str(rng.randrange(0, 16)),
    "BLENDFACTOR": lambda: hex(rng.getrandbits(32)),
    "FOGCOLOR": lambda: hex(rng.getrandbits(32)),
    "FOGSTART": f, "FOGEND": f, "FOGDENSITY": f,
    "FOGTABLEMODE": lambda: f'"{rng.choice(["NONE", "EXP", "EXP2", "LINEAR"])}"',
    "FOGVERTEXMODE": lambda: f'"{rng.choice(["NONE", "EXP", "EXP2", "LINEAR"])}"',
}
STAGE = {
    "MINFILTER": lambda: f'"{rng.choice(["POINT", "LINEAR"])}"',
    "MAGFILTER": lambda: f'"{rng.choice(["POINT", "LINEAR"])}"',
    "MIPFILTER": lambda: f'"{rng.choice(["NONE", "POINT", "LINEAR"])}"',
    "ADDRESSU": lambda: f'"{rng.choice(["WRAP", "CLAMP", "MIRROR", "BORDER", "MIRRORONCE"])}"',
    "ADDRESSV": lambda: f'"{rng.choice(["WRAP", "CLAMP", "MIRROR", "BORDER", "MIRRORONCE"])}"',
    "COLOROP": lambda: f'"{rng.choice(["MODULATE", "SELECTARG1", "SELECTARG2", "ADD", "DISABLE", "MODULATE2X", "ADDSIGNED", "SUBTRACT", "BLENDDIFFUSEALPHA", "DOTPRODUCT3"])}"',
    "ALPHAOP": lambda: f'"{rng.choice(["MODULATE", "SELECTARG1", "SELECTARG2", "DISABLE"])}"',
    "BORDERCOLOR": lambda: hex(rng.getrandbits(32)),
    "MAXMIPLEVEL": lambda: str(rng.randrange(0, 8)),
    "MIPMAPLODBIAS": f,
}
FVFS = ["XYZ", "XYZ | DIFFUSE", "XYZ | PSIZE | DIFFUSE", "XYZRHW | DIFFUSE",
        "XYZRHW | PSIZE | DIFFUSE", "XYZ | PSIZE | DIFFUSE | SPECULAR | TEX1",
        "XYZRHW | PSIZE | DIFFUSE | TEX1", "XYZ | NORMAL | DIFFUSE", "XYZ | TEX2"]
def fields(fvf):
    n = {"XYZ": 3, "XYZRHW": 4}[fvf.split(" | ")[0]]
    out = [f for _ in range(n)]
    for part in fvf.split(" | ")[1:]:
        if part == "PSIZE": out.append(f)
        elif part in ("DIFFUSE", "SPECULAR"): out.append(lambda: hex(rng.getrandbits(32)))
        elif part == "NORMAL": out += [f, f, f]
        elif part.startswith("TEX"): out += [f, f] * int(part[3:])
    return out

def scene(k):
    w, h = rng.choice([1, 7, 32, 64, 100, 256]), rng.choice([1, 5, 32, 64, 90, 256])
    s = [f"format = 1", "[target]", f"width = {w}", f"height = {h}", f"clear = {hex(rng.getrandbits(32))}"]
    if rng.random() < 0.3:
        s += ["[viewport]", f"x = {rng.randrange(0, w)}", f"y = {rng.randrange(0, h)}", "width = 1", "height = 1"]
    if rng.random() < 0.4:
        s += ["[transform]", f"view = {{ look_at_lh = {{ eye = [{f()}, {f()}, {f()}], at = [0, 0, 1], up = [0, 1, 0] }} }}",
              f"projection = {{ perspective_fov_lh = {{ fovy = {f()}, aspect = {f()}, zn = {f()}, zf = {f()} }} }}"]
    s.append("[states]")
    for key in rng.sample(sorted(STATES), rng.randrange(0, 10)):
        s.append(f"{key} = {STATES[key]()}")
    if rng.random() < 0.6:
        s.append("[stage.0]")
        for key in rng.sample(sorted(STAGE), rng.randrange(0, 6)):
            s.append(f"{key} = {STAGE[key]()}")
        tw, th = rng.choice([(1, 1), (2, 2), (4, 3), (8, 8)])
        texels = ", ".join(hex(rng.getrandbits(32)) for _ in range(tw * th))
        s += ["[[texture]]", "stage = 0", f"width = {tw}", f"height = {th}", f"texels = [{texels}]"]
    for _ in range(rng.randrange(0, 4)):
        fvf = rng.choice(FVFS)
        cols = fields(fvf)
        rows = ", ".join("[" + ", ".join(c() for c in cols) + "]" for _ in range(rng.randrange(0, 40)))
        s += ["[[draw]]", f'fvf = "{fvf}"', f"vertices = [{rows}]"]
    if rng.random() < 0.25:
        s += ["[[emitter]]", f"max_particles = {rng.choice([1, 100, 5000])}", f"rate = {rng.choice(['1', '1000', '1e6', '0.01'])}",
              f"lifetime = [{rng.uniform(0, 3):.3f}, {rng.uniform(3, 6):.3f}]", f"size = [{f()}, {f()}]",
              f'blend = "{rng.choice(["additive", "alpha"])}"']
        s += ["[animation]", f"frames = {rng.choice([1, 2, 30])}", f"fps = {rng.choice([1, 30, 60])}"]
    text = "\n".join(s) + "\n"
    if rng.random() < 0.2:  # one corruption: a line dropped, duplicated or a value mangled
        lines = text.split("\n")
        i = rng.randrange(len(lines))
        op = rng.randrange(3)
        if op == 0: del lines[i]
        elif op == 1: lines.insert(i, lines[i])
        else: lines[i] = lines[i].replace("=", "= \"\\u001b[2J\"\r#", 1)
        text = "\n".join(lines)
    return text

counts = {"ok": 0, "error": 0}
bad = []
peak = 0
t0 = time.time()
for k in range(N):
    text = scene(k)
    path = f"{WORK}/s.toml"
    out = f"{WORK}/out.png"
    if os.path.exists(out): os.remove(out)
    open(path, "w").write(text)
    args = [BIN, "render", path, "-o", out]
    if "[animation]" in text and rng.random() < 0.5: args += ["--frame", str(rng.randrange(0, 2))]
    try:
        p = subprocess.run(["/usr/bin/time", "-f", "RSS %M"] + args, capture_output=True, timeout=60)
    except subprocess.TimeoutExpired:
        bad.append((k, "timeout")); open(f"{WORK}/bad{k}.toml", "w").write(text); continue
    err = p.stderr.decode(errors="replace").strip().split("\n")
    rss = int(err[-1].split()[1]); peak = max(peak, rss); err = err[:-1]
    warn = [l for l in err if l.startswith("warning:")]
    rest = [l for l in err if not l.startswith("warning:") and not l.startswith("Command exited")]
    leftovers = glob.glob(f"{WORK}/.pointillist-*")
    problem = None
    if p.returncode == 0:
        if not os.path.exists(out) or rest: problem = "exit 0 without output or with errors"
        counts["ok"] += 1
    elif p.returncode == 1:
        if len(rest) != 1 or os.path.exists(out): problem = f"exit 1 with {len(rest)} lines"
        elif any(ord(c) < 32 for c in rest[0]): problem = "control character in the error"
        counts["error"] += 1
        open(f"{WORK}/errors.txt", "a").write(rest[0] + "\n" if rest else "")
    else:
        problem = f"exit {p.returncode}"
    if leftovers: problem = "leftover temporary file"
    if problem:
        bad.append((k, problem, rest[:2])); open(f"{WORK}/bad{k}.toml", "w").write(text)
        for l in leftovers: os.remove(l)
print(f"seed {SEED}: {N} scenes in {time.time() - t0:.0f} s: {counts}, peak RSS {peak} KB, problems {len(bad)}")
for b in bad[:20]: print("  ", b)
