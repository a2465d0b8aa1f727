#!/usr/bin/env python3
"""Bad-input fuzzer for the `tracksim` binary (issue 15).

Generates N inputs that are bad by construction (mutations of the bundled scenario and vehicle
files: values beyond the engine's range, NaN, huge counts, over-long fixed arrays, tables written
as arrays, bad track names, special files, a PNG header claiming 10^6 x 10^6 pixels, over-long
lines, huge hulls, bad CLI flags), runs `tracksim check` and `tracksim run` on each under a
time limit and a memory limit, and counts how each ended:

  panic      exit 101 or "panicked" on stderr
  hang       killed by the time limit
  oom        "memory allocation ... failed" or killed by a signal
  wrong_ok   exit 0 for an input that is bad by construction, or NaN / null written
  disagree   `check` and `run` disagree (one accepts what the other refuses)
  long_msg   an error message of more than 20 kB (an echoed line)
  ok         refused with exit 2 (or 3 for a run that went unstable), message short

Usage: scripts/fuzz-inputs.py BINARY [--n 300] [--seed 1] [--timeout 20] [--keep DIR]
Prints one line per bad outcome and a JSON summary last.
"""

import argparse
import json
import os
import random
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import tomllib
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = [
    "scenarios/packbot_flat.toml",
    "scenarios/packbot_step.toml",
    "scenarios/packbot_stairs.toml",
    "scenarios/packbot_rough.toml",
    "scenarios/packbot_mesh.toml",
    "scenarios/packbot_turn.toml",
    "scenarios/quince_flat.toml",
]
MEM_LIMIT = 3 << 30  # bytes of address space per process
SKIP_INT_KEYS = {"seed"}


# --- a small TOML writer (top-level tables as sections, everything below inline) -------------
def tstr(s):
    return json.dumps(s, ensure_ascii=False)


def tval(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return tstr(v)
    if isinstance(v, list):
        return "[" + ", ".join(tval(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{tstr(k)} = {tval(x)}" for k, x in v.items()) + " }"
    raise TypeError(v)


def dumps(doc):
    lines = []
    for k, v in doc.items():
        if not isinstance(v, dict):
            lines.append(f"{tstr(k)} = {tval(v)}")
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"[{tstr(k)}]")
            for kk, vv in v.items():
                lines.append(f"{tstr(kk)} = {tval(vv)}")
    return "\n".join(lines) + "\n"


# --- walking the document ------------------------------------------------------------------------
def leaves(doc, path=()):
    """(path, value) for every value, depth first."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield path + (k,), v
            yield from leaves(v, path + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield path + (i,), v
            yield from leaves(v, path + (i,))


def set_at(doc, path, value):
    for p in path[:-1]:
        doc = doc[p]
    doc[path[-1]] = value


def is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


EXTREME_FLOATS = [1e39, -1e39, 1e300, -1e300, float("nan"), float("inf"), 1e154, 3.5e38]


def mutate(rng, sdoc, vdoc):
    """Mutates the scenario or vehicle document in place; returns a description or None."""
    doc, which = (sdoc, "scenario") if rng.random() < 0.5 else (vdoc, "vehicle")
    kind = rng.choice(["float", "float", "int", "array", "table", "name", "positive_tiny"])
    all_leaves = [
        (p, v) for p, v in leaves(doc) if not (p and p[0] in ("randomize", "description"))
    ]
    if kind == "float":
        cands = [(p, v) for p, v in all_leaves if isinstance(v, float)]
        if not cands:
            return None
        p, _ = rng.choice(cands)
        x = rng.choice(EXTREME_FLOATS)
        set_at(doc, p, x)
        return f"{which} {p} = {x}"
    if kind == "positive_tiny":
        # Masses, sizes and radii of 1e-300: finite in f64, zero in f32.
        cands = [
            (p, v)
            for p, v in all_leaves
            if isinstance(p[-1], str)
            and isinstance(v, float)
            and v > 0
            and any(p[-1].endswith(s) for s in ("mass_kg", "radius_m", "width_m", "length_m"))
        ]
        if not cands:
            return None
        p, _ = rng.choice(cands)
        set_at(doc, p, 1e-300)
        return f"{which} {p} = 1e-300"
    if kind == "int":
        cands = [
            (p, v)
            for p, v in all_leaves
            if isinstance(v, int) and not isinstance(v, bool) and p[-1] not in SKIP_INT_KEYS
            and isinstance(p[-1], str)
        ]
        if not cands:
            return None
        p, _ = rng.choice(cands)
        x = rng.choice([2**63 - 1, 10**6, 10**9])
        set_at(doc, p, x)
        return f"{which} {p} = {x}"
    if kind == "array":
        cands = [
            (p, v)
            for p, v in all_leaves
            if isinstance(v, list) and len(v) in (2, 3) and all(is_num(x) for x in v)
            and p[-1] not in ("choice", "omit_segments")
            and not (isinstance(p[-1], str) and p[-1] in ("uniform", "integers"))
        ]
        if not cands:
            return None
        p, v = rng.choice(cands)
        set_at(doc, p, v + [99.0])
        return f"{which} {p} with an extra entry"
    if kind == "table":
        cands = [
            (p, v)
            for p, v in all_leaves
            if isinstance(v, dict) and v and all(is_num(x) for x in v.values())
        ]
        if not cands:
            return None
        p, v = rng.choice(cands)
        set_at(doc, p, list(v.values()))
        return f"{which} {p} as an array"
    if kind == "name":
        tracks = vdoc.get("tracks", [])
        if not tracks:
            return None
        t = rng.choice(tracks)
        t["name"] = rng.choice(["le,ft", "le\nft", 'le"ft', "left side", ""])
        return f"vehicle track name {t['name']!r}"
    return None


def png_claiming(w, h):
    """A tiny PNG whose header claims w x h pixels (16-bit grey)."""

    def chunk(t, data):
        return struct.pack(">I", len(data)) + t + data + struct.pack(">I", zlib.crc32(t + data))

    ihdr = struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)
    idat = zlib.compress(b"\0" * 64)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def special_case(rng, case_dir, sdoc, vdoc):
    """Special files and workloads; returns (description, scenario path or None, extra args)."""
    kind = rng.choice(["vehicle_dev", "vehicle_dir", "vehicle_fifo", "png_huge", "png_dev",
                       "long_line", "hull", "grousers", "dt", "flag_duration", "scenario_dev",
                       "flag_nan", "start_below"])
    if kind == "vehicle_dev":
        sdoc["vehicle"]["file"] = "/dev/zero"
    elif kind == "vehicle_dir":
        sdoc["vehicle"]["file"] = "."
    elif kind == "vehicle_fifo":
        os.mkfifo(case_dir / "fifo.toml")
        sdoc["vehicle"]["file"] = "fifo.toml"
    elif kind == "png_huge":
        (case_dir / "huge.png").write_bytes(png_claiming(10**6, 10**6))
        sdoc["terrain"]["heightfields"] = [
            {"file": "huge.png", "size_x_m": 4.0, "size_y_m": 4.0, "max_z_m": 0.1}
        ]
    elif kind == "png_dev":
        sdoc["terrain"]["heightfields"] = [
            {"file": "/dev/urandom", "size_x_m": 4.0, "size_y_m": 4.0, "max_z_m": 0.1}
        ]
    elif kind == "long_line":
        sdoc.setdefault("simulation", {})["method"] = "x" * 2_000_000
    elif kind == "hull":
        n = 20_000
        vdoc["body"]["shape"] = {
            "type": "convex",
            "points_m": [[rng.uniform(-0.2, 0.2), rng.uniform(-0.1, 0.1), rng.uniform(0, 0.1)]
                         for _ in range(n)],
        }
    elif kind == "grousers":
        for t in vdoc.get("tracks", []):
            if "grousers" in t:
                t["grousers"]["count"] = 10**6
    elif kind == "dt":
        sdoc.setdefault("simulation", {})["dt_s"] = 1e-9
    elif kind == "flag_duration":
        return "run --duration 1e300", None, ["--duration", "1e300"]
    elif kind == "flag_nan":
        return "run --duration nan", None, ["--duration", "nan"]
    elif kind == "scenario_dev":
        return "scenario file /dev/zero", Path("/dev/zero"), []
    elif kind == "start_below":
        sdoc["vehicle"]["z_m"] = -1.0
    return kind, None, []


def limit():
    resource.setrlimit(resource.RLIMIT_AS, (MEM_LIMIT, MEM_LIMIT))
    os.setsid()


def run(binary, args, timeout, cwd):
    try:
        p = subprocess.run([binary] + args, capture_output=True, timeout=timeout, cwd=cwd,
                           preexec_fn=limit)
        return p.returncode, p.stderr.decode(errors="replace") + p.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired as e:
        return "timeout", ""


def classify(rc, text):
    if rc == "timeout":
        return "hang"
    if rc == 101 or "panicked" in text:
        return "panic"
    if "memory allocation" in text or (isinstance(rc, int) and rc < 0):
        return "oom"
    if len(text) > 20_000:
        return "long_msg"
    return None


def outputs_bad(out_dir):
    s = out_dir / "summary.json"
    t = out_dir / "trajectory.csv"
    if s.exists() and "null" in s.read_text().replace('"odometry": null', ""):
        pass
    if t.exists():
        body = t.read_text()
        if "NaN" in body or "inf" in body:
            return True
    return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=20)
    ap.add_argument("--keep")
    a = ap.parse_args()
    binary = str(Path(a.binary).resolve())
    rng = random.Random(a.seed)
    counts = {}
    work = Path(a.keep) if a.keep else Path(tempfile.mkdtemp(prefix="tracksim-fuzz-"))
    work.mkdir(parents=True, exist_ok=True)
    i = 0
    while i < a.n:
        src = ROOT / rng.choice(SCENARIOS)
        sdoc = tomllib.loads(src.read_text())
        vfile = (src.parent / sdoc["vehicle"]["file"]).resolve()
        vdoc = tomllib.loads(vfile.read_text())
        case = work / f"case-{i:04d}"
        if case.exists():
            shutil.rmtree(case)
        case.mkdir()
        shutil.copytree(ROOT / "scenarios/assets", case / "assets")
        sdoc["vehicle"]["file"] = "v.toml"
        sdoc.setdefault("simulation", {})["duration_s"] = 0.3
        extra = []
        scen = case / "s.toml"
        if rng.random() < 0.7:
            what = mutate(rng, sdoc, vdoc)
            if what is None:
                shutil.rmtree(case)
                continue
        else:
            what, scen_override, extra = special_case(rng, case, sdoc, vdoc)
            if scen_override is not None:
                scen = scen_override
        (case / "s.toml").write_text(dumps(sdoc))
        (case / "v.toml").write_text(dumps(vdoc))
        i += 1
        rc_c, text_c = run(binary, ["check", str(scen)], a.timeout, case)
        out = case / "out"
        rc_r, text_r = run(binary, ["run", str(scen), "--no-plot", "--quiet", "--out", str(out)]
                           + extra, a.timeout, case)
        verdict = classify(rc_c, text_c) or classify(rc_r, text_r)
        if verdict is None:
            if rc_r == 0 and outputs_bad(out):
                verdict = "wrong_ok"
            elif rc_r == 0 and not extra:
                verdict = "wrong_ok"
            elif rc_c == 0 and extra:
                verdict = None  # flags are not checked by `check`
            elif rc_c == 0:
                verdict = "wrong_ok"
            elif (rc_c == 0) != (rc_r == 0):
                verdict = "disagree"
        verdict = verdict or "ok"
        counts[verdict] = counts.get(verdict, 0) + 1
        if verdict != "ok":
            first = (text_c + text_r).strip().splitlines()[:2]
            print(f"{verdict:9} {case.name} {what[:100]!s}: check {rc_c}, run {rc_r}: "
                  f"{' | '.join(first)[:300]}", flush=True)
        elif not a.keep:
            shutil.rmtree(case, ignore_errors=True)
    print(json.dumps({"binary": a.binary, "n": a.n, "seed": a.seed, "counts": counts}))
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    main()
