"""The tutorial's script (docs/tutorial.md): open a scene, edit its cage, compare two schemes,
save pictures. Run it from the repository root:

    build/bin/quadplan run-script docs/examples/first_scene.py [OUTPUT_DIR]
"""
import pathlib
import sys

import numpy as np

import quadplan as qp

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "tutorial-output")
out.mkdir(parents=True, exist_ok=True)

# 1. Open a scene: the cage is planned at once (one subdivision plan per face).
scene = qp.load("scenes/creased_box.json")
print(scene)
print("plans in use:", scene.plan_stats()["unique_plans"])

# 2. Edit the cage. Select the top face by a predicate and pull it out.
top = scene.select("face", lambda f: f.normal[1] > 0.9)
report = scene.extrude(top, distance=0.6)
print(report)  # how many faces were re-planned: only those near the extrusion

# Tilt the new cap and make its rim infinitely sharp.
cap = qp.Selection.of_faces(report.result_faces)
scene.rotate(cap, axis=(0, 0, 1), degrees=15)
rim = scene.convert(cap, "edge")
scene.set_creases(rim, 10.0)
print("creases now:", len(scene.creases))

# Moving vertices never re-plans; it only refreshes the control points of nearby faces.
corner = scene.select("vertex", lambda v: v.position[0] < -0.9 and v.position[1] < -0.9 and v.position[2] < -0.9)
move = scene.translate(corner, (-0.3, -0.3, -0.3))
assert move.replanned_faces == 0

# 3. Compare two schemes: the exact plans against uniform refinement's flat triangles.
camera = qp.Camera(eye=(3.5, 3.0, 5.0), target=(0, 0.4, 0), fov=40)
numbers = scene.compare(["plans", "uniform"], tess=8, camera=camera)
for s in numbers["schemes"]:
    print(f'{s["name"]:8} max error {s["max_rel_error"]:.2e} of the diagonal, {s["triangles"]} triangles, '
          f'{s["frame_ms"]:.1f} ms a frame')

# 4. Save pictures: each scheme's surface side by side, and uniform's error as a heat map.
plans = scene.render("plans", size=(400, 320), camera=camera)
uniform = scene.render("uniform", size=(400, 320), camera=camera, wireframe=True, options={"level": 2})
heat, error = scene.render_error("uniform", size=(400, 320), camera=camera)
qp.write_png(str(out / "compare.png"), np.hstack([plans, uniform, heat]))
print("wrote", out / "compare.png", "- uniform's largest error:", f'{error["max_rel_error"]:.2e}')

# 5. Save the edited scene (undo history is not saved; the cage and its tags are).
scene.save(str(out / "edited_box.json"))
assert qp.load(out / "edited_box.json").cage == scene.cage
