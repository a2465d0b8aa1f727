"""Issue 16.6 probe: the six Table IV cases (Quince, 0.1 m/s, contact slop 10 mm, friction 0.6)
at 8 solver iterations and at 4, with the 0.1 kg and the 0.5 kg link-mass floor.

Usage: python3 bench/quince_iterations.py TRACKSIM_BINARY [OUT_DIR]
Differs from `tracksim validate` in one point: the front flippers start flat and are driven to
their angle from t = 0 (a scenario file cannot set the initial flipper angle); the 8-iteration
rows reproduce validate's S S F S S F all the same.
"""
import itertools
import json
import os
import subprocess
import sys
import tempfile

B = sys.argv[1]
V = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "vehicles", "quince.toml")
OUT = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp()
os.makedirs(OUT, exist_ok=True)
cases=[(0,0.04),(0,0.12),(0,0.19),(45,0.12),(45,0.24),(45,0.38)]
variants=[("8it_0.1kg",8,0.1),("4it_0.1kg",4,0.1),("4it_0.5kg",4,0.5)]
for (name,it,mass),(deg,h) in itertools.product(variants,cases):
    t=f'''description = "probe"
[vehicle]
file = "{V}"
x_m = 0.0
[terrain.ground]
friction = 0.6
[[terrain.boxes]]
centre_m = [{1.0+0.75}, 0.0, {h/2}]
size_m = [1.5, 3.0, {h}]
friction = 0.6
[simulation]
dt_s = 0.001
duration_s = 60.0
min_link_mass_kg = {mass}
solver_iterations = {it}
contact_slop_m = 0.01
[outcome]
success_x_m = 1.4
max_tilt_deg = 75.0
[[commands]]
t_s = 0.0
belt_speed_mps = 0.1
flipper_angle_deg = {{ front_left = {deg}.0, front_right = {deg}.0, rear_left = 0.0, rear_right = 0.0 }}
'''
    p=os.path.join(OUT, f"{name}_{deg}_{int(h*1000)}.toml"); open(p,"w").write(t)
    r=subprocess.run([B,"run",p,"--json","--quiet","--no-plot","--out",p[:-5]],capture_output=True,text=True)
    if r.returncode!=0: print(name,deg,h,"ERR",r.stderr[-300:],flush=True); continue
    s=json.loads(r.stdout)
    on_top = s["final_pose"]["z"] > h+0.05
    print(name,deg,int(h*1000),s["outcome"],round(s.get("outcome_time_s",0),1),"on_top" if on_top else "low",round(s["final_pose"]["x"],2),"rtf",round(s["real_time_factor"],1),"max_link_error_mm",round(1000*s["max_link_error_m"],2),flush=True)
