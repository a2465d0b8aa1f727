"""Same-run benchmark: tracksim against MuJoCo on a PackBot-like vehicle (issue 16).

Builds the PackBot 510 of ``vehicles/packbot510.toml`` in MuJoCo the way a user choosing a
simulator would (MJCF written here, MuJoCo's default solver: Newton, 100 iterations, pyramidal
cones; ``implicitfast`` integrator, as MuJoCo's documentation recommends with velocity
actuators), with the tracks as

- ``mj_surfacevel``: grouser-less tracks with a moving surface (``geom/surfacevel``): per side a
  box for the runs (constant surface velocity) and two pulley cylinders (rotational surface
  velocity), no degrees of freedom;
- ``mj_wheels4`` / ``mj_wheels13``: 4 or 13 driven wheels per side reaching the grouser tips
  (radius 0.09 m), as tracksim's ``wheels4`` / ``wheels13``;
- ``mj_plates40``: a closed chain of 40 hinged plates with a 5 x 8 mm grouser each, closed by a
  ``connect`` equality, wrapped round a driven sprocket and a free idler with flanges;
- ``mj_okada40`` (issue 44): the paper's method itself built in MuJoCo: per track 4 segment
  links on the chassis (the two runs on slide joints along x, the two arcs on hinge joints about
  the pulley axles), each with its belt shape and the grousers whose footprints lie on its
  segment at rest (40 a track at the pitch L / 40, boxes 5 x 8 mm x track width), velocity
  actuators at belt speed, and the paper's rollback after every step (a link that has moved one
  pitch along the belt has its joint position set back by exactly one pitch, in Python between
  ``mj_step`` calls, inside the timed window).

Same dt (1 ms), drive (0.3 m/s), ground friction (0.6), masses (11 kg body, 1 kg per belt) and
10 s simulated. Then ``tracksim bench --cases packbot`` (every method) runs once per repeat,
interleaved with the MuJoCo models (mj..., tracksim, mj..., tracksim, ...) and, optionally,
the ``contact_floor`` example. Only stepping (with mj_okada40's rollback) is timed. Prints a
markdown report (ratios first; issue 44's okada2020 / mj_okada40 and okada2020 / wheels4 as the
ratio of the medians and the median of the per-repeat ratios) and writes it with the raw
figures (JSON) into ``--out``.

``--steps`` also drives every model (MuJoCo and tracksim) at a 0.08 / 0.10 / 0.12 m step of
friction 0.6, edge 0.5 m ahead, for 8 s: climbed when the body origin passes x = 1.2 m on top
without tilting past 60 deg (``scenarios/packbot_step.toml``'s outcome).

``--frontier`` (issue 58; MuJoCo only, no tracksim binary) instead sweeps ``mj_okada40`` over
the time step (``--frontier-dt``), the solver and its iteration cap (``--frontier-solvers``)
and the contact time constant (``--frontier-solref``, each raised to 2 dt), the model otherwise
as above, and for each setting measures the CPU time per simulated second
(``time.process_time`` of the stepping and the rollback on the flat drive), the flat speed and
drift, the step-climb verdicts at ``--frontier-steps`` and the skid-steer turn rate (belts at
+-0.3 m/s); it prints a markdown table, names the fastest setting with the verdicts of the
default setting at 1 ms, and writes ``frontier.md`` and ``frontier.json`` into ``--out``:
    bench/mujoco/.venv/bin/python bench/mujoco/bench.py --frontier --out /tmp/mj_frontier
"""

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import mujoco
import numpy as np

DT = 0.001  # s
SPEED = 0.3  # m/s, belt speed
FRICTION = 0.6
BODY = dict(mass=11.0, size=(0.50, 0.25, 0.10))  # kg, m (full sizes)
BELT_MASS = 1.0  # kg per track
TRACK_Y = 0.1625  # m, track mid-plane
TRACK_W = 0.075  # m
AXLE_X = 0.255  # m, pulley centres at +-AXLE_X, z = 0
PULLEY_R = 0.082  # m, belt outer surface at the pulleys
BELT_T = 0.01  # m
GROUSER_H, GROUSER_L = 0.008, 0.005  # m
GROUSERS = 40
TIP_R = PULLEY_R + GROUSER_H  # m, 0.09: the grouser tips, the wheels' radius
Z0 = TIP_R + 0.002  # m, initial body height: dropped 2 mm onto the ground
STEP_EDGE_X = 0.5  # m
SUCCESS_X = 1.2  # m
MAX_TILT_DEG = 60.0

# Collision bits: ground/terrain 1; body 8 (touches the terrain only); track parts touching the
# terrain (surface-velocity geoms, wheels, plates) 2 or 4; chain wheels 16 (touch plates only).
GROUND = 'contype="1" conaffinity="1"'
BODYC = 'contype="8" conaffinity="1"'
ONGROUND = 'contype="2" conaffinity="1"'
PLATE = 'contype="4" conaffinity="17" solref="0.004 1"'
CHAINWHEEL = 'contype="16" conaffinity="4"'
PLATE_ARMATURE = 1e-5  # kg m^2, hinge armature of the plates (MuJoCo conditioning)


def header(name, terrain):
    return f"""<mujoco model="{name}">
  <option timestep="{DT}" integrator="implicitfast" gravity="0 0 -9.81"/>
  <default><geom friction="{FRICTION} 0.005 0.0001" condim="3"/></default>
  <worldbody>
    <geom name="ground" type="plane" size="20 20 0.1" {GROUND}/>
{terrain}
    <body name="chassis" pos="0 0 {Z0}">
      <freejoint name="root"/>
      <geom name="hull" type="box" size="{BODY['size'][0] / 2} {BODY['size'][1] / 2} {BODY['size'][2] / 2}" mass="{BODY['mass']}" {BODYC}/>
"""


def step_terrain(h):
    if h is None:
        return ""
    return (f'    <geom name="step" type="box" pos="{STEP_EDGE_X + 1.0} 0 {h / 2}" '
            f'size="1.0 1.5 {h / 2}" {GROUND}/>')


def model_surfacevel(h):
    """Grouser-less tracks with a moving surface: no degrees of freedom in the tracks."""
    xml = header("surfacevel", step_terrain(h))
    w = SPEED / PULLEY_R
    for s, y in (("l", TRACK_Y), ("r", -TRACK_Y)):
        # Runs: a box between the pulley centres; its whole surface moves at -SPEED along x
        # (only the bottom face meets anything).
        xml += (f'      <geom name="run_{s}" type="box" pos="0 {y} 0" '
                f'size="{AXLE_X} {TRACK_W / 2} {PULLEY_R}" mass="{BELT_MASS / 2}" '
                f'surfacevel="{-SPEED} 0 0 0 0 0" {ONGROUND}/>\n')
        # Pulleys: cylinders about y (euler -90 0 0: geom z = world +y), surface turning at
        # w = v / r, so that the bottom moves back and the front face down.
        for e, x in (("rear", -AXLE_X), ("front", AXLE_X)):
            xml += (f'      <geom name="{e}_{s}" type="cylinder" pos="{x} {y} 0" euler="-90 0 0" '
                    f'size="{PULLEY_R} {TRACK_W / 2}" mass="{BELT_MASS / 4}" '
                    f'surfacevel="0 0 0 0 0 {w}" {ONGROUND}/>\n')
    xml += "    </body>\n  </worldbody>\n</mujoco>\n"
    return xml, TIP_R - GROUSER_H


def model_wheels(n, h):
    """n driven wheels per side on the lower run, radius to the grouser tips."""
    xml = header(f"wheels{n}", step_terrain(h))
    acts = ""
    for s, y in (("l", TRACK_Y), ("r", -TRACK_Y)):
        for i in range(n):
            x = -AXLE_X + 2 * AXLE_X * i / (n - 1)
            xml += (f'      <body name="w{s}{i}" pos="{x} {y} 0">\n'
                    f'        <joint name="j{s}{i}" type="hinge" axis="0 1 0"/>\n'
                    f'        <geom type="cylinder" euler="-90 0 0" size="{TIP_R} {TRACK_W / 2}" '
                    f'mass="{BELT_MASS / n}" {ONGROUND}/>\n      </body>\n')
            acts += f'    <velocity joint="j{s}{i}" kv="20" ctrlrange="-100 100"/>\n'
    xml += f"    </body>\n  </worldbody>\n  <actuator>\n{acts}  </actuator>\n</mujoco>\n"
    return xml, TIP_R


def chain_points(n):
    """n hinge points at equal arc length on the plates' mid-thickness loop (track frame)."""
    r = PULLEY_R - BELT_T / 2
    straight, arc = 2 * AXLE_X, math.pi * r
    total = 2 * straight + 2 * arc
    pts = []
    for k in range(n):
        s = total * k / n
        if s < straight:  # bottom run, rear to front
            pts.append((-AXLE_X + s, -r))
            continue
        s -= straight
        if s < arc:  # front arc, bottom to top
            a = -math.pi / 2 + s / r
            pts.append((AXLE_X + r * math.cos(a), r * math.sin(a)))
            continue
        s -= arc
        if s < straight:  # top run, front to rear
            pts.append((AXLE_X - s, r))
            continue
        s -= straight  # rear arc, top to bottom
        a = math.pi / 2 + s / r
        pts.append((-AXLE_X + r * math.cos(a), r * math.sin(a)))
    return pts, r


def model_plates(n, h):
    """A closed chain of n hinged plates with grousers per side, sprocket-driven by friction."""
    xml = header(f"plates{n}", step_terrain(h))
    pts, r = chain_points(n)
    # The chain lies on each wheel as a polygon: the plates' inner faces are nearest the centre
    # at mid-chord; 1 mm clearance.
    chord = math.dist(pts[0], pts[1])
    wheel_r = math.sqrt(r * r - chord * chord / 4) - BELT_T / 2 - 0.001
    half = math.asin(chord / (2 * r))
    r_eff = chord / (2 * half)  # chain speed = w * r_eff on a polygon
    acts, eqs = "", ""
    for s, y in (("l", TRACK_Y), ("r", -TRACK_Y)):
        for e, x in (("spr", -AXLE_X), ("idl", AXLE_X)):
            fr = 'friction="1.5 0.005 0.0001"' if e == "spr" else 'friction="0.6 0.005 0.0001"'
            xml += (f'      <body name="{e}{s}" pos="{x} {y} 0">\n'
                    f'        <joint name="{e}{s}" type="hinge" axis="0 1 0"/>\n'
                    f'        <geom type="cylinder" euler="-90 0 0" size="{wheel_r} {TRACK_W / 2}" '
                    f'mass="0.5" {fr} {CHAINWHEEL}/>\n')
            for fy in (-1, 1):
                xml += (f'        <geom type="cylinder" pos="0 {fy * (TRACK_W / 2 + 0.002)} 0" '
                        f'euler="-90 0 0" size="{wheel_r + 0.012} 0.001" mass="0.01" '
                        f'{CHAINWHEEL}/>\n')
            xml += "      </body>\n"
        acts += f'    <velocity joint="spr{s}" kv="20" ctrlrange="-100 100"/>\n'
    xml += "    </body>\n"
    # The chains: plate k between hinge points k and k+1, nested (plate 0 free), the loop
    # closed by a connect equality.
    for s, y in (("l", TRACK_Y), ("r", -TRACK_Y)):
        ind = "    "
        prev = None
        for k in range(n):
            a, b = pts[k], pts[(k + 1) % n]
            ang = math.atan2(b[1] - a[1], b[0] - a[0])  # chord direction in x-z
            ln = math.dist(a, b)
            if prev is None:
                # the root plate's frame at hinge point a, x along the chord; rotation about y
                # by -ang maps x to the chord (x-z plane, z up)
                xml += (f'{ind}<body name="p{s}{k}" pos="{a[0]} {y} {a[1] + Z0}" '
                        f'euler="0 {-math.degrees(ang)} 0">\n{ind}  <freejoint/>\n'
                        f'{ind}  <site name="start{s}"/>\n')
            else:
                dang = ang - prev[1]
                xml += (f'{ind}<body name="p{s}{k}" pos="{prev[0]} 0 0" '
                        f'euler="0 {-math.degrees(dang)} 0">\n'
                        f'{ind}  <joint type="hinge" axis="0 1 0" armature="{PLATE_ARMATURE}"/>\n')
            plate_mass = BELT_MASS / n
            # plate between x = 0 and x = ln (0.5 mm gap each end); the loop runs bottom run
            # forward, up the front, so the outward normal is local -z
            xml += (f'{ind}  <geom type="box" pos="{ln / 2} 0 0" '
                    f'size="{ln / 2 - 0.0005} {TRACK_W / 2} {BELT_T / 2}" mass="{plate_mass * 0.8}" {PLATE}/>\n'
                    f'{ind}  <geom type="box" pos="{ln / 2} 0 {-(BELT_T / 2 + GROUSER_H / 2)}" '
                    f'size="{GROUSER_L / 2} {TRACK_W / 2} {GROUSER_H / 2}" mass="{plate_mass * 0.2}" {PLATE}/>\n')
            if k == n - 1:
                xml += f'{ind}  <site name="end{s}" pos="{ln} 0 0"/>\n'
            prev = (ln, ang)
            ind += "  "
        for k in range(n):
            ind = ind[:-2]
            xml += f"{ind}</body>\n"
        eqs += f'    <connect site1="end{s}" site2="start{s}"/>\n'
    xml += (f"  </worldbody>\n  <equality>\n{eqs}  </equality>\n"
            f"  <actuator>\n{acts}  </actuator>\n</mujoco>\n")
    return xml, r_eff


#: Velocity gain of mj_okada40's link actuators, N per m/s of belt-speed error (the hinges'
#: actuators act through a gear of the arc radius, so the gain is in belt units on every link).
BELT_KV = 2000.0


def okada_segments():
    """The belt path of the paper's method (track frame x-z, at the belt's outer surface, where
    the grousers' footprints lie), as (kind, start s, length, data) in the belt's direction of
    motion from the rear top tangent point (tracksim's segment 0): top run forward, front arc
    down, bottom run backward, rear arc up. A positive belt speed drives the vehicle forward."""
    straight, arc = 2 * AXLE_X, math.pi * PULLEY_R
    return [("top", 0.0, straight, (-AXLE_X, PULLEY_R, 1.0)),
            ("front", straight, arc, AXLE_X),
            ("bottom", straight + arc, straight, (AXLE_X, -PULLEY_R, -1.0)),
            ("rear", 2 * straight + arc, arc, -AXLE_X)]


def model_okada(n, h):
    """The paper's method (Okada et al. 2020, Sec. III): per track 4 segment links on the
    chassis (the 2 runs on slide joints along x, the 2 arcs on hinge joints about the pulley
    axles), each carrying its belt shape and the grousers whose footprints lie on its segment
    at rest (n a track at pitch L / n, boxes 5 x 8 mm x track width), driven by velocity
    actuators at belt speed. The rollback (`OkadaRollback`, after every step) keeps the track's
    shape."""
    xml = header(f"okada{n}", step_terrain(h))
    segs = okada_segments()
    loop = sum(seg[2] for seg in segs)
    pitch = loop / n
    acts = ""
    for s, y in (("l", TRACK_Y), ("r", -TRACK_Y)):
        for kind, s0, ln, data in segs:
            # grousers k at arc length k * pitch whose footprint lies on [s0, s0 + ln) at rest
            ks = [k for k in range(n) if s0 - 1e-9 <= k * pitch < s0 + ln - 1e-9]
            mass = BELT_MASS * ln / loop
            g_mass = BELT_MASS * 0.2 / n
            b_mass = mass - g_mass * len(ks)
            name = f"{kind}{s}"
            if kind in ("top", "bottom"):
                x0, z, d = data  # start x, height of the outer surface, direction of motion
                zb = z - math.copysign(BELT_T / 2, z)  # the belt inside the outer surface
                zg = z + math.copysign(GROUSER_H / 2, z)  # the grousers outside it
                xml += (f'      <body name="{name}" pos="0 {y} 0">\n'
                        f'        <joint name="{name}" type="slide" axis="1 0 0"/>\n'
                        f'        <geom type="box" pos="0 0 {zb}" size="{AXLE_X} {TRACK_W / 2} '
                        f'{BELT_T / 2}" mass="{b_mass}" {ONGROUND}/>\n')
                for k in ks:
                    xg = x0 + d * (k * pitch - s0)
                    xml += (f'        <geom type="box" pos="{xg} 0 {zg}" size="{GROUSER_L / 2} '
                            f'{TRACK_W / 2} {GROUSER_H / 2}" mass="{g_mass}" {ONGROUND}/>\n')
                # actuator velocity = gear * qdot = belt speed
                acts += (f'    <velocity joint="{name}" gear="{d}" kv="{BELT_KV}" '
                         f'ctrlrange="-10 10"/>\n')
            else:
                xc = data  # the pulley axle; the belt turns about +y at v / r on both arcs
                a0 = math.pi / 2 if kind == "front" else -math.pi / 2  # start angle in x-z
                xml += (f'      <body name="{name}" pos="{xc} {y} 0">\n'
                        f'        <joint name="{name}" type="hinge" axis="0 1 0"/>\n'
                        f'        <geom type="cylinder" euler="-90 0 0" size="{PULLEY_R} '
                        f'{TRACK_W / 2}" mass="{b_mass}" {ONGROUND}/>\n')
                rg = PULLEY_R + GROUSER_H / 2
                for k in ks:
                    # angle in the x-z plane (from +x towards +z); a turn about +y goes from
                    # +z towards +x, so the angle decreases along the belt
                    th = a0 - (k * pitch - s0) / PULLEY_R
                    # box local x radial (a turn of -th about y maps x to (cos th, 0, sin th))
                    xml += (f'        <geom type="box" pos="{rg * math.cos(th)} 0 '
                            f'{rg * math.sin(th)}" euler="0 {-math.degrees(th)} 0" '
                            f'size="{GROUSER_H / 2} {TRACK_W / 2} {GROUSER_L / 2}" '
                            f'mass="{g_mass}" {ONGROUND}/>\n')
                acts += (f'    <velocity joint="{name}" gear="{PULLEY_R}" kv="{BELT_KV}" '
                         f'ctrlrange="-10 10"/>\n')
            xml += "      </body>\n"
    xml += f"    </body>\n  </worldbody>\n  <actuator>\n{acts}  </actuator>\n</mujoco>\n"
    return xml, 1.0  # ctrl = belt speed (gears)


class OkadaRollback:
    """The paper's rollback, after every step: a segment link that has moved one grouser pitch
    p along the belt from its rest pose (a run: p along x in its direction of motion; an arc:
    p / r about the axle) has its joint position set back by exactly one pitch, so that grouser
    n - 1 takes grouser n's place and the track keeps its shape. Joint velocities are kept.
    Forward belt motion only (the bench drives at +0.3 m/s): a link's joint stays in [0, p)."""

    def __init__(self, m, d):
        loop = sum(seg[2] for seg in okada_segments())
        pitch = loop / GROUSERS
        adr, step = [], []
        for j in range(m.njnt):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or ""
            if name[:-1] in ("top", "bottom", "front", "rear"):
                adr.append(m.jnt_qposadr[j])
                # joint-coordinate change of one pitch in the belt's direction of motion
                step.append({"top": pitch, "bottom": -pitch}.get(name[:-1], pitch / PULLEY_R))
        self.lo, self.hi = min(adr), max(adr) + 1
        assert self.hi - self.lo == len(adr), "the links' joints are consecutive in qpos"
        order = sorted(range(len(adr)), key=lambda i: adr[i])
        self.step = [step[i] for i in order]
        self.qs = d.qpos[self.lo:self.hi]  # a view of d's joint positions, taken once
        self.rollbacks = 0

    def __call__(self, d):
        # plain Python on the 8 joint positions (a view taken once): numpy's per-call
        # overheads cost more than the check
        qs = self.qs
        for i, (q, p) in enumerate(zip(qs.tolist(), self.step)):
            if q / p >= 1.0:  # one pitch (or more) along the belt since the rest pose
                qs[i] = q - p
                self.rollbacks += 1


MODELS = {
    "mj_surfacevel": lambda h: model_surfacevel(h),
    "mj_wheels4": lambda h: model_wheels(4, h),
    "mj_wheels13": lambda h: model_wheels(13, h),
    "mj_plates40": lambda h: model_plates(GROUSERS, h),
    "mj_okada40": lambda h: model_okada(GROUSERS, h),
}

#: Models with work between steps (the paper's rollback): name -> its maker, given the model
#: and its data.
AFTER_STEP = {"mj_okada40": OkadaRollback}


def build(name, h=None):
    """The model, its data and the radius its controls are divided by (bench/yardstick.py)."""
    xml, r = MODELS[name](h)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d, r


def build_stepped(name, h=None):
    """`build` and the model's work after every step (None: none; steps may then be taken
    several at a time)."""
    m, d, r = build(name, h)
    after = AFTER_STEP[name](m, d) if name in AFTER_STEP else None
    return m, d, r, after


def advance(m, d, after, n):
    """n steps, the work after every step included."""
    if after is None:
        mujoco.mj_step(m, d, nstep=n)
        return
    for _ in range(n):
        mujoco.mj_step(m, d)
        after(d)


def drive(m, d, r, v):
    """Sets every velocity actuator to v / r (wheels, sprockets)."""
    if m.nu:
        d.ctrl[:] = v / r


def tilt_deg(d):
    q = d.qpos[3:7]  # chassis quaternion w x y z
    # body z axis in world: third column of the rotation matrix
    zz = 1 - 2 * (q[1] ** 2 + q[2] ** 2)
    return math.degrees(math.acos(max(-1.0, min(1.0, zz))))


def time_mujoco(name, duration):
    m, d, r, after = build_stepped(name)
    drive(m, d, r, SPEED)
    steps = int(round(duration / DT))
    chunk = 10
    stepping, contacts, samples = 0.0, 0, 0
    x2 = None
    for i in range(steps // chunk):
        t0 = time.perf_counter()
        advance(m, d, after, chunk)
        stepping += time.perf_counter() - t0
        contacts += d.ncon
        samples += 1
        if x2 is None and d.time >= 2.0:
            x2, t2 = d.qpos[0], d.time
        if not np.all(np.isfinite(d.qpos)):
            raise RuntimeError(f"{name}: state not finite at t = {d.time:.3f} s")
    speed = (d.qpos[0] - x2) / (d.time - t2) if x2 is not None else float("nan")
    res = dict(rtf=d.time / stepping, us_per_step=stepping * 1e6 / steps,
               contacts=contacts / samples, speed=speed, height=float(d.qpos[2]),
               lateral=float(d.qpos[1]), tilt=tilt_deg(d), nv=m.nv, nefc=int(d.nefc))
    if after is not None:
        res["rollbacks"] = after.rollbacks
    return res


def climb_mujoco(name, h, duration=8.0):
    m, d, r, after = build_stepped(name, h)
    drive(m, d, r, SPEED)
    worst = 0.0
    while d.time < duration:
        advance(m, d, after, 10)
        worst = max(worst, tilt_deg(d))
        if not np.all(np.isfinite(d.qpos)) or worst > MAX_TILT_DEG:
            break
    ok = d.qpos[0] > SUCCESS_X and d.qpos[2] > h and worst <= MAX_TILT_DEG
    return dict(climbed=bool(ok), x=float(d.qpos[0]), z=float(d.qpos[2]), max_tilt=worst)


#: The suffix of a tracksim row run on the bench case `packbot_open_top` (the PackBot with its
#: top runs as links without colliders, vehicles/packbot510_open_top.toml).
OPEN_TOP = " (open top)"


def run_tracksim_bench(binary, duration, methods, case="packbot", suffix=""):
    cmd = [binary, "bench", "--repeat", "1", "--cases", case, "--duration", str(duration),
           "--json"]
    if methods:
        cmd += ["--methods", ",".join(methods)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    case = json.loads(out)["cases"][0]
    return {mm["name"] + suffix: dict(rtf=mm["rtf_median"], us_per_step=mm["us_per_step"],
                                      contacts=mm["contacts_per_step"])
            for mm in case["methods"] if mm["error"] is None}


def run_contact_floor(binary, args):
    """The contact_floor example with its arguments GROUSERS BODIES ITERATIONS [SHAPE [GROUND]]."""
    out = subprocess.run([binary, *args], check=True, capture_output=True, text=True).stdout
    # "36 grousers on 6 bodies, 4 iterations: 32.0 us/step (real-time factor 31), 156 contacts"
    us = float(out.split(":")[1].split("us/step")[0])
    contacts = int(out.split("),")[1].split("contacts")[0])
    return dict(rtf=1e3 / us, us_per_step=us, contacts=contacts)


def climb_tracksim(binary, scenario, h, methods):
    """Writes the step scenario with height h next to a copy of the vehicle path and runs it."""
    vehicles = os.path.join(os.path.dirname(os.path.abspath(scenario)), "..", "vehicles")
    res = {}
    for meth in methods:
        file = "packbot510_open_top.toml" if meth.endswith(OPEN_TOP) else "packbot510.toml"
        res.update(climb_tracksim_one(binary, os.path.join(vehicles, file), h, meth))
    return res


def climb_tracksim_one(binary, vehicle, h, meth):
    """One method (a name ending in OPEN_TOP: that method on `vehicle`) at step height h."""
    text = f"""description = "issue 16 step sweep, {h} m"
[vehicle]
file = "{os.path.abspath(vehicle)}"
[terrain.ground]
friction = {FRICTION}
[[terrain.boxes]]
centre_m = [{STEP_EDGE_X + 1.0}, 0.0, {h / 2}]
size_m = [2.0, 3.0, {h}]
friction = {FRICTION}
[simulation]
dt_s = {DT}
duration_s = 8.0
[outcome]
success_x_m = {SUCCESS_X}
max_tilt_deg = {MAX_TILT_DEG}
[[commands]]
t_s = 0.0
belt_speed_mps = {SPEED}
"""
    res = {}
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "step.toml")
        with open(path, "w") as f:
            f.write(text)
        name = meth.removesuffix(OPEN_TOP)
        out = subprocess.run([binary, "run", path, "--method", name, "--json", "--quiet",
                              "--no-plot", "--out", os.path.join(tmp, "out")],
                             capture_output=True, text=True)
        if out.returncode != 0:
            res[meth] = dict(climbed=False, error=out.stderr.strip()[-200:])
            return res
        s = json.loads(out.stdout)
        res[meth] = dict(climbed=s.get("outcome") == "success", outcome=s.get("outcome"))
    return res


def machine():
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return dict(cpu=cpu, nproc=os.cpu_count(), python=platform.python_version(),
                mujoco=mujoco.__version__, date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()))


def summarise(runs):
    out = {}
    for name, rs in runs.items():
        rtf = [r["rtf"] for r in rs]
        out[name] = dict(rtf_median=statistics.median(rtf), rtf_min=min(rtf), rtf_max=max(rtf),
                         us_per_step=statistics.median(r["us_per_step"] for r in rs),
                         contacts=statistics.median(r["contacts"] for r in rs), runs=rtf)
        for key in ("speed", "height", "lateral", "tilt", "nv", "rollbacks"):
            if key in rs[0]:
                out[name][key] = statistics.median(r[key] for r in rs)
    return out


def issue44_rows(summary, runs):
    """okada2020 / mj_okada40 and okada2020 / wheels4 (issue 44's targets): the ratio of the
    medians and the median of the per-repeat ratios (each repeat times both close together:
    the interleaved figure, steadier on a shared machine), with each target."""
    rows = []
    for num, den, goal in (("okada2020", "mj_okada40", 2.0), ("okada2020", "wheels4", 0.6)):
        if not all(k in summary and k in runs for k in (num, den)):
            continue
        of_medians = summary[num]["rtf_median"] / summary[den]["rtf_median"]
        pairs = [a["rtf"] / b["rtf"] for a, b in zip(runs[num], runs[den])]
        rows.append(dict(ratio=f"{num} / {den}", target=goal, of_medians=of_medians,
                         interleaved=statistics.median(pairs), per_repeat=pairs))
    return rows


def report(info, summary, loads, climbs, runs=None):
    mj = [k for k in summary if k.startswith("mj_")]
    ts = [k for k in summary if not k.startswith("mj_") and not k.startswith("floor")]
    lines = [f"Machine: {info['cpu']}, {info['nproc']} cores; MuJoCo {info['mujoco']}, "
             f"Python {info['python']}; {info['date']}; load average (1 min) during the run "
             f"{min(loads):.2f}-{max(loads):.2f}.", ""]
    lines += ["### Ratios (tracksim method RTF / MuJoCo model RTF, medians of the same run)", "",
              "| tracksim method | " + " | ".join(mj) + " |",
              "|---|" + "---:|" * len(mj)]
    for t in ts:
        lines.append(f"| {t} | " + " | ".join(
            f"{summary[t]['rtf_median'] / summary[k]['rtf_median']:.2f}" for k in mj) + " |")
    rows = issue44_rows(summary, runs or {})
    if rows:
        lines += ["", "### Targets of issue 44 (RTF ratio, same run)", "",
                  "| ratio | target | ratio of medians | median of per-repeat ratios | per repeat |",
                  "|---|---:|---:|---:|---|"]
        for w in rows:
            lines.append(
                f"| {w['ratio']} | >= {w['target']:.2f} | {w['of_medians']:.2f} | "
                f"{w['interleaved']:.2f} ({'met' if w['interleaved'] >= w['target'] else 'not met'})"
                f" | {', '.join(f'{x:.2f}' for x in w['per_repeat'])} |")
    floors = [k for k in summary if k.startswith("floor ")]
    targets = [("mj_plates40", 25.0), ("mj_surfacevel", 0.25), ("wheels4", 0.6)] + \
        [(k, 1 / 1.3) for k in floors]
    cands = [t for t in ("okada2020", "okada2020" + OPEN_TOP, "okada2020_clustered",
                         "okada2020_clustered" + OPEN_TOP, "okada2020_line_tips")
             if t in summary]
    if cands:
        lines += ["", "### Targets of issue 16 (RTF ratio, same run)", "",
                  "| ratio | target | " + " | ".join(cands) + " |",
                  "|---|---:|" + "---:|" * len(cands)]
        for k, goal in targets:
            if k not in summary:
                continue
            vals = [summary[c]["rtf_median"] / summary[k]["rtf_median"] for c in cands]
            lines.append(f"| method / {k} | >= {goal:.2f} | " + " | ".join(
                f"{v:.2f} ({'met' if v >= goal else 'not met'})" for v in vals) + " |")
    lines += ["", "### Every model, this machine, this day", "",
              "| model | RTF median | RTF min-max | us/step | contacts/step | speed m/s (2-10 s) | height m |",
              "|---|---:|---:|---:|---:|---:|---:|"]
    for k, s in summary.items():
        sp = f"{s['speed']:.3f}" if "speed" in s and math.isfinite(s["speed"]) else "-"
        hz = f"{s['height']:.4f}" if "height" in s else "-"
        lines.append(f"| {k} | {s['rtf_median']:.1f} | {s['rtf_min']:.1f}-{s['rtf_max']:.1f} | "
                     f"{s['us_per_step']:.1f} | {s['contacts']:.0f} | {sp} | {hz} |")
    if climbs:
        hs = sorted({h for c in climbs.values() for h in c})
        lines += ["", "### Step climbing (friction 0.6, 0.3 m/s, 8 s)", "",
                  "| model | " + " | ".join(f"{h:.2f} m" for h in hs) + " |",
                  "|---|" + "---|" * len(hs)]
        for k, c in climbs.items():
            lines.append(f"| {k} | " + " | ".join(
                ("yes" if c[h]["climbed"] else "no") if h in c else "-" for h in hs) + " |")
    return "\n".join(lines) + "\n"


# --- The frontier of mj_okada40 over dt and solver settings (issue 58) -----------------------

#: MuJoCo's solvers by the names --frontier-solvers takes.
SOLVERS = {"newton": mujoco.mjtSolver.mjSOL_NEWTON, "cg": mujoco.mjtSolver.mjSOL_CG,
           "pgs": mujoco.mjtSolver.mjSOL_PGS}
#: MuJoCo's default contact time constant (solref "0.02 1"), the models' contact softness.
DEFAULT_TIMECONST = 0.02  # s
FRONTIER_MODEL = "mj_okada40"
#: Sampling of the frontier's runs (tilt, climb, divergence, yaw), s of simulated time: a
#: whole number of steps at every dt of the default grid.
FRONTIER_CHECK = 0.004
FRONTIER_CLIMB_S = 8.0  # s, as --steps
FRONTIER_TURN_S, FRONTIER_TURN_FROM = 5.0, 1.0  # s: turn for 5 s, yaw rate mean over 1-5 s
BAD_STATE = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
             mujoco.mjtWarning.mjWARN_BADQACC)


class OkadaRollbackBothWays(OkadaRollback):
    """`OkadaRollback` for belts running either way (the skid-steer turn drives one track
    backward): a link that has moved back past its rest pose is set forward by one pitch, so
    that its joint stays in [0, p) as under forward motion (the same track shapes)."""

    def __call__(self, d):
        qs = self.qs
        for i, (q, p) in enumerate(zip(qs.tolist(), self.step)):
            f = q / p
            if f >= 1.0:
                qs[i] = q - p
                self.rollbacks += 1
            elif f < 0.0:
                qs[i] = q + p
                self.rollbacks += 1


def frontier_label(s):
    tc = "default" if s["timeconst"] is None else f"{s['timeconst'] * 1e3:g} ms"
    return f"dt {s['dt'] * 1e3:g} ms, {s['solver']} {s['iterations']}, solref {tc}"


def frontier_settings(dts_ms, solvers, timeconsts):
    """The grid: every dt x solver entry x time constant. A solver entry is NAME:ITERATIONS,
    optionally @DT+DT (ms: only at those dts) and/or /d (only MuJoCo's default contact
    softness). A time constant is raised to 2 dt (MuJoCo's own floor, `refsafe`); one that
    then equals another at that dt is dropped, as is one at or above the default's 0.02 s."""
    out = []
    for dt_ms in dts_ms:
        dt = dt_ms * 1e-3
        for entry in solvers:
            only_default = entry.endswith("/d")
            entry = entry.removesuffix("/d")
            spec, _, at = entry.partition("@")
            name, _, iters = spec.partition(":")
            if name not in SOLVERS:
                sys.exit(f"bench.py: unknown solver {name!r} in --frontier-solvers; "
                         f"known: {', '.join(SOLVERS)}")
            if at and not any(abs(float(x) - dt_ms) < 1e-9 for x in at.split("+")):
                continue
            seen = set()
            for tc in timeconsts:
                if tc is not None:
                    if only_default:
                        continue
                    tc = max(tc, 2 * dt)
                    if tc >= DEFAULT_TIMECONST - 1e-12:
                        continue
                key = None if tc is None else round(tc, 9)
                if key in seen:
                    continue
                seen.add(key)
                out.append(dict(dt=dt, solver=name, iterations=int(iters or 100), timeconst=tc))
    return out


def frontier_build(s, h=None, rollback=OkadaRollback):
    """mj_okada40 as built for the other modes, then the setting's options: the time step, the
    solver and its iteration cap, and every geom's contact time constant (damping ratio 1 kept;
    None: MuJoCo's default, untouched). MuJoCo's reset of a state gone bad is off, so that it
    is seen (its time kept) and the run stopped."""
    m, d, r = build(FRONTIER_MODEL, h)
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_AUTORESET
    m.opt.timestep = s["dt"]
    m.opt.solver = SOLVERS[s["solver"]]
    m.opt.iterations = s["iterations"]
    if s["timeconst"] is not None:
        m.geom_solref[:, 0] = s["timeconst"]
    mujoco.mj_forward(m, d)
    return m, d, r, rollback(m, d)


def bad_state(d):
    return (not np.all(np.isfinite(d.qpos))) or any(d.warning[w].number for w in BAD_STATE)


def frontier_flat(s, duration, repeats):
    """The flat drive (0.3 m/s, `duration` s): CPU time of the stepping and the rollback
    (time.process_time, chunks of 20 ms simulated), the speed over the last half, the lateral
    drift (y at the end), solver iterations (sampled at the chunks' ends). Deterministic, so the
    repeats only re-time it."""
    cpus = []
    for _ in range(repeats):
        m, d, r, after = frontier_build(s)
        drive(m, d, r, SPEED)
        per = int(round(0.02 / s["dt"]))
        chunks = int(round(duration / 0.02))
        cpu, niter, xh, th, diverged = 0.0, [], None, None, None
        for i in range(chunks):
            t0 = time.process_time()
            advance(m, d, after, per)
            cpu += time.process_time() - t0
            niter.append(int(d.solver_niter[:max(1, d.nisland)].max()))
            if 2 * (i + 1) == chunks:
                xh, th = float(d.qpos[0]), d.time
            if bad_state(d):
                diverged = d.time
                break
        cpus.append(cpu / d.time)
    res = dict(cpu_per_sim_s=statistics.median(cpus), cpu_runs=cpus,
               speed=(float(d.qpos[0]) - xh) / (d.time - th) if xh is not None and diverged is None
               else float("nan"),
               drift=float(d.qpos[1]), height=float(d.qpos[2]), tilt=tilt_deg(d),
               niter_mean=statistics.fmean(niter), niter_max=max(niter), nefc=int(d.nefc),
               ncon=int(d.ncon), rollbacks=after.rollbacks, diverged=diverged)
    res["rtf"] = 1.0 / res["cpu_per_sim_s"]
    return res


def frontier_climb(s, h):
    """`climb_mujoco` at this setting, checked every FRONTIER_CHECK s (tilt, divergence, the
    first time the body origin is past SUCCESS_X on top)."""
    m, d, r, after = frontier_build(s, h)
    drive(m, d, r, SPEED)
    per = max(1, int(round(FRONTIER_CHECK / s["dt"])))
    worst, t_climb, diverged = 0.0, None, None
    while d.time < FRONTIER_CLIMB_S - 1e-9:
        advance(m, d, after, per)
        if bad_state(d):
            diverged = d.time
            break
        worst = max(worst, tilt_deg(d))
        if worst > MAX_TILT_DEG:
            break
        if t_climb is None and d.qpos[0] > SUCCESS_X and d.qpos[2] > h:
            t_climb = d.time
    ok = diverged is None and d.qpos[0] > SUCCESS_X and d.qpos[2] > h and worst <= MAX_TILT_DEG
    return dict(climbed=bool(ok), t_climb=t_climb if ok else None, x=float(d.qpos[0]),
                z=float(d.qpos[2]), max_tilt=worst, diverged=diverged)


def yaw(d):
    w, x, y, z = d.qpos[3:7]
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def frontier_turn(s):
    """Skid-steer in place: left belt +0.3 m/s, right -0.3 m/s, FRONTIER_TURN_S s on flat
    ground; the mean yaw rate (rad/s, positive to the left) from FRONTIER_TURN_FROM s on."""
    m, d, r, after = frontier_build(s, rollback=OkadaRollbackBothWays)
    for a in range(m.nu):
        jname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.actuator_trnid[a, 0])
        d.ctrl[a] = (SPEED if jname.endswith("l") else -SPEED) / r
    per = max(1, int(round(FRONTIER_CHECK / s["dt"])))
    unwrapped, last, y0, t0, diverged = 0.0, yaw(d), None, None, None
    while d.time < FRONTIER_TURN_S - 1e-9:
        advance(m, d, after, per)
        if bad_state(d):
            diverged = d.time
            break
        a = yaw(d)
        unwrapped += math.remainder(a - last, 2 * math.pi)
        last = a
        if y0 is None and d.time >= FRONTIER_TURN_FROM - 1e-9:
            y0, t0 = unwrapped, d.time
    rate = (unwrapped - y0) / (d.time - t0) if y0 is not None and diverged is None else float("nan")
    return dict(rate=rate, x=float(d.qpos[0]), y=float(d.qpos[1]), diverged=diverged,
                rollbacks=after.rollbacks)


def flat_fault(w):
    """Why a row's flat drive or turn is not a vehicle driving on the ground (None: it is): the
    state went bad, or the flat drive ended tipped past MAX_TILT_DEG or off the ground (body
    origin outside 0.05-0.2 m; 0.09 m at rest)."""
    f, t = w["flat"], w["turn"]
    if f["diverged"] is not None:
        return f"flat drive went bad at {f['diverged']:.3f} s"
    if f["tilt"] > MAX_TILT_DEG:
        return f"flat drive ended tilted {f['tilt']:.0f} deg"
    if not 0.05 <= f["height"] <= 0.2:
        return f"flat drive ended at z = {f['height']:.2f} m"
    if t["diverged"] is not None:
        return f"turn went bad at {t['diverged']:.3f} s"
    return None


def same_as(w, ref):
    return w["verdicts"] == ref["verdicts"] and flat_fault(w) is None


def verdicts(climbs, heights):
    return "".join("D" if climbs[h]["diverged"] is not None else
                   ("S" if climbs[h]["climbed"] else "F") for h in heights)


def frontier_report(info, rows, heights, ref, loads, duration, repeats):
    lines = [f"Machine: {info['cpu']}, {info['nproc']} cores; MuJoCo {info['mujoco']}, "
             f"Python {info['python']}; {info['date']}; load average (1 min) during the sweep "
             f"{min(loads):.2f}-{max(loads):.2f}.", "",
             f"`{FRONTIER_MODEL}` only. CPU s per sim s: `time.process_time` of the stepping "
             f"and the rollback on the flat {duration:g} s drive at {SPEED} m/s (median of "
             f"{repeats}); RTF = its inverse. Speed: mean over the last {duration / 2:g} s; "
             f"drift: y at the end. Steps (friction {FRICTION}, edge {STEP_EDGE_X} m ahead, "
             f"{FRONTIER_CLIMB_S:g} s): S (climbed, the first time the body origin was past "
             f"x = {SUCCESS_X} m on top) or F (D: the state went bad). Turn: belts at "
             f"+-{SPEED} m/s, mean yaw rate {FRONTIER_TURN_FROM:g}-{FRONTIER_TURN_S:g} s. "
             f"Iters: solver iterations a step (mean / max, sampled every 20 ms of the flat "
             f"drive). Same verdicts: the same S/F series as the reference, with the flat drive "
             f"and the turn on the ground (not gone bad, not tipped past {MAX_TILT_DEG:g} deg, "
             f"the flat drive's body origin at 0.05-0.2 m at the end). Reference: "
             f"{frontier_label(ref['setting'])}.", "",
             "| dt ms | solver | solref timeconst | CPU s per sim s | RTF | speed m/s | "
             "drift m | iters | steps " + "/".join(f"{h:g}" for h in heights) +
             " m | turn rad/s (x ref) | same verdicts as the 1 ms default |",
             "|---:|---|---|---:|---:|---:|---:|---:|---|---:|---|"]
    for w in rows:
        s, f = w["setting"], w["flat"]
        tc = "default (20 ms)" if s["timeconst"] is None else f"{s['timeconst'] * 1e3:g} ms"
        steps = " ".join(f"D {w['climbs'][h]['diverged']:.2f}s"
                         if w["climbs"][h]["diverged"] is not None else
                         (f"S {w['climbs'][h]['t_climb']:.2f}s" if w["climbs"][h]["climbed"]
                          else "F") for h in heights)
        rate = w["turn"]["rate"]
        rel = rate / ref["turn"]["rate"] if ref["turn"]["rate"] else float("nan")
        fault = flat_fault(w)
        same = ("yes" if same_as(w, ref) else "no") + (f" ({fault})" if fault else "")
        mark = "**" if w is ref else ""
        lines.append(
            f"| {mark}{s['dt'] * 1e3:g}{mark} | {s['solver']} {s['iterations']} | {tc} | "
            f"{f['cpu_per_sim_s']:.4f} | {f['rtf']:.1f} | {f['speed']:.4f} | {f['drift']:+.4f} | "
            f"{f['niter_mean']:.1f} / {f['niter_max']} | {steps} | {rate:.3f} ({rel:.2f}) | "
            f"{same} |")
    same = [w for w in rows if same_as(w, ref)]
    best = min(same, key=lambda w: w["flat"]["cpu_per_sim_s"])
    lines += ["", f"Reference verdicts ({frontier_label(ref['setting'])}): "
              f"{ref['verdicts']} at " + ", ".join(f"{h:g}" for h in heights) + " m.",
              f"**Fastest setting with the reference's verdicts: "
              f"{frontier_label(best['setting'])}: {best['flat']['cpu_per_sim_s']:.4f} CPU s "
              f"per sim s (RTF {best['flat']['rtf']:.1f}), "
              f"{ref['flat']['cpu_per_sim_s'] / best['flat']['cpu_per_sim_s']:.2f}x the "
              f"reference's {ref['flat']['cpu_per_sim_s']:.4f}.**"]
    close = [w for w in same
             if abs(w["flat"]["speed"] / ref["flat"]["speed"] - 1) <= 0.05
             and abs(w["turn"]["rate"] / ref["turn"]["rate"] - 1) <= 0.10]
    if close:
        b2 = min(close, key=lambda w: w["flat"]["cpu_per_sim_s"])
        lines.append(f"Fastest with the same verdicts, the flat speed within 5 % and the turn "
                     f"rate within 10 % of the reference's: {frontier_label(b2['setting'])}: "
                     f"{b2['flat']['cpu_per_sim_s']:.4f} CPU s per sim s "
                     f"(RTF {b2['flat']['rtf']:.1f}).")
    return "\n".join(lines) + "\n", best


def run_frontier(a):
    heights = [float(h) for h in a.frontier_steps.split(",") if h]
    dts = [float(x) for x in a.frontier_dt.split(",") if x]
    tcs = [None if x == "default" else float(x) for x in a.frontier_solref.split(",") if x]
    settings = frontier_settings(dts, [x for x in a.frontier_solvers.split(",") if x], tcs)
    ref_s = dict(dt=DT, solver="newton", iterations=100, timeconst=None)
    # the reference first (every row is compared with it), whether or not the grid holds it
    settings = [ref_s] + [s for s in settings if s != ref_s]
    info = machine()
    os.makedirs(a.out, exist_ok=True)
    rows, loads, ref = [], [], None
    cpu0 = time.process_time()
    for n, s in enumerate(settings):
        loads.append(os.getloadavg()[0])
        print(f"[{n + 1}/{len(settings)}] {frontier_label(s)}", file=sys.stderr, flush=True)
        w = dict(setting=s, flat=frontier_flat(s, a.duration, a.repeat),
                 climbs={h: frontier_climb(s, h) for h in heights}, turn=frontier_turn(s))
        w["verdicts"] = verdicts(w["climbs"], heights)
        if ref is None:
            ref = w
        rows.append(w)
        print(f"    {w['flat']['cpu_per_sim_s']:.4f} CPU s/sim s, speed "
              f"{w['flat']['speed']:.4f}, drift {w['flat']['drift']:+.4f}, steps {w['verdicts']}, "
              f"turn {w['turn']['rate']:.3f} rad/s; sweep CPU so far "
              f"{time.process_time() - cpu0:.0f} s", file=sys.stderr, flush=True)
        with open(os.path.join(a.out, "frontier.json"), "w") as f:
            json.dump(dict(machine=info, loads=loads, heights=heights, rows=[
                dict(w, climbs={str(h): c for h, c in w["climbs"].items()}) for w in rows]),
                f, indent=1)
    rows.sort(key=lambda w: (w["setting"]["dt"], list(SOLVERS).index(w["setting"]["solver"]),
                             -w["setting"]["iterations"],
                             -(w["setting"]["timeconst"] or DEFAULT_TIMECONST)))
    text, best = frontier_report(info, rows, heights, ref, loads, a.duration, a.repeat)
    text += f"\nSweep CPU time (this process): {time.process_time() - cpu0:.0f} s.\n"
    with open(os.path.join(a.out, "frontier.json"), "w") as f:
        json.dump(dict(machine=info, loads=loads, heights=heights, reference=ref["setting"],
                       fastest_same_verdicts=best["setting"], sweep_cpu_s=time.process_time() - cpu0,
                       rows=[dict(w, climbs={str(h): c for h, c in w["climbs"].items()})
                             for w in rows]), f, indent=1)
    with open(os.path.join(a.out, "frontier.md"), "w") as f:
        f.write(text)
    print(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tracksim", help="path to the release tracksim binary (not with --frontier)")
    ap.add_argument("--contact-floor", help="path to the contact_floor example binary")
    ap.add_argument("--scenario", help="scenarios/packbot_flat.toml (not with --frontier)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--duration", type=float, default=10.0, help="simulated s per run")
    ap.add_argument("--models", default=",".join(MODELS), help="MuJoCo models, comma-separated")
    ap.add_argument("--methods", default="", help="tracksim methods (default: all)")
    ap.add_argument("--floor", default="36:6:4:box:tile,36:6:4:capsule:tile",
                    help="contact_floor runs GROUSERS:BODIES:ITERATIONS[:SHAPE[:GROUND]], "
                         "comma-separated")
    ap.add_argument("--steps", default="", help="step heights to climb, m, e.g. 0.08,0.10,0.12")
    ap.add_argument("--out", default="bench_out/mujoco")
    ap.add_argument("--frontier", action="store_true",
                    help=f"instead: sweep {FRONTIER_MODEL} over dt and solver settings (MuJoCo "
                         "only; --repeat times the flat drive, --duration its length); writes "
                         "frontier.md and frontier.json into --out")
    ap.add_argument("--frontier-dt", default="0.5,1,2,4", help="time steps, ms")
    ap.add_argument("--frontier-solvers", default="newton:100,newton:4,newton:3,newton:2,cg:100,cg:10,"
                    "pgs:20@1+4/d,pgs:8@1+4/d",
                    help="NAME:ITERATIONS[@DT+DT][/d], comma-separated (newton, cg, pgs; @: only "
                         "at those dts, ms; /d: only at the default contact softness)")
    ap.add_argument("--frontier-solref", default="default,0.008,0.004,0.002",
                    help="contact time constants, s ('default': MuJoCo's 0.02), each raised to "
                         "2 dt")
    ap.add_argument("--frontier-steps", default="0.08,0.10,0.11,0.12", help="step heights, m")
    a = ap.parse_args()
    if a.repeat < 1 or a.duration <= 0:
        sys.exit("bench.py: --repeat must be >= 1 and --duration > 0")
    if a.frontier:
        run_frontier(a)
        return
    if not a.tracksim or not a.scenario:
        sys.exit("bench.py: --tracksim and --scenario are required (except with --frontier)")
    models = [m for m in a.models.split(",") if m]
    for m in models:
        if m not in MODELS:
            sys.exit(f"bench.py: unknown --models entry {m!r}; known: {', '.join(MODELS)}")
    methods = [m for m in a.methods.split(",") if m]
    floors = [f.split(":") for f in a.floor.split(",") if f] if a.contact_floor else []
    info = machine()
    runs, loads = {}, []
    for r in range(a.repeat):
        for m in models:
            loads.append(os.getloadavg()[0])
            print(f"[{r + 1}/{a.repeat}] {m}", file=sys.stderr, flush=True)
            runs.setdefault(m, []).append(time_mujoco(m, a.duration))
        loads.append(os.getloadavg()[0])
        print(f"[{r + 1}/{a.repeat}] tracksim bench", file=sys.stderr, flush=True)
        for k, v in run_tracksim_bench(a.tracksim, a.duration, methods).items():
            runs.setdefault(k, []).append(v)
        for k, v in run_tracksim_bench(a.tracksim, a.duration,
                                       ["okada2020", "okada2020_clustered"], "packbot_open_top",
                                       OPEN_TOP).items():
            runs.setdefault(k, []).append(v)
        for f in floors:
            runs.setdefault("floor " + ":".join(f), []).append(run_contact_floor(a.contact_floor, f))
    summary = summarise(runs)
    climbs = {}
    heights = [float(h) for h in a.steps.split(",") if h]
    for h in heights:
        print(f"step {h} m", file=sys.stderr, flush=True)
        for m in models:
            climbs.setdefault(m, {})[h] = climb_mujoco(m, h)
        ts = methods or [k for k in summary if not k.startswith(("mj_", "floor"))]
        for k, v in climb_tracksim(a.tracksim, a.scenario, h, ts).items():
            climbs.setdefault(k, {})[h] = v
    text = report(info, summary, loads, climbs, runs)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "mujoco_bench.md"), "w") as f:
        f.write(text)
    with open(os.path.join(a.out, "mujoco_bench.json"), "w") as f:
        json.dump(dict(machine=info, loads=loads, summary=summary, runs=runs,
                       climbs={k: {str(h): v for h, v in c.items()} for k, c in climbs.items()}),
                  f, indent=1)
    print(text)


if __name__ == "__main__":
    main()
