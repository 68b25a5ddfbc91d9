"""Scene tests through the Python module: each builds or loads a scene, edits it, renders it, and
asserts on numbers and on golden pictures (conftest.py says how pictures are compared).

Run by ctest (scene_tests.*); by hand:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/scenes -q [--update-goldens]
"""
import json
import math

import numpy as np
import pytest

import quadplan as qp
from conftest import SCENES, image_difference, run_cli

SIZE = (160, 120)


def faces_around(scene, vertices):
    """Faces with a corner in `vertices`."""
    vertices = set(vertices)
    return {i for i, face in enumerate(scene.faces) if vertices & set(face)}


def one_ring_faces(scene, vertices):
    """Faces whose 1-ring (faces sharing a vertex with them) holds a vertex of `vertices`: the
    sub-faces a move of those vertices gives new control points."""
    near = faces_around(scene, vertices)
    near_vertices = {v for f in near for v in scene.faces[f]}
    return faces_around(scene, near_vertices)


def assert_matches_rebuild(scene):
    assert scene.differences_from_rebuild() == []
    check = scene.check_limit(samples=5)
    assert check["pass"], check


# ---- loading, statistics, evaluation -------------------------------------------------------

def test_default_scene_loads_with_plans_and_numbers():
    scene = qp.load(SCENES / "default.json")
    info = scene.info()
    assert info["faces"] == scene.face_count > 0
    assert info["vertices"] == scene.vertex_count
    stats = scene.plan_stats()
    assert stats["depth"] == 6 and stats["subfaces"] == scene.subface_count
    assert 0 < stats["unique_plans"] <= stats["subfaces"]
    assert stats["stencils"] > 0 and stats["bytes"] > 0
    memory = scene.memory()
    assert memory["plans"] == stats["unique_plans"] or memory["plans"] >= stats["unique_plans"]
    assert memory["stencil_bytes"] > 0 and memory["quadtree_bytes"] > 0
    assert_matches_rebuild(scene)


def test_evaluation_matches_opensubdiv_and_is_batched(cube):
    u = np.linspace(0, 1, 7)
    positions, du, dv = cube.evaluate(0, u, 0.5, derivatives=True)
    assert positions.shape == (7, 3) and du.shape == (7, 3)
    # A smooth cube's limit surface lies strictly inside the cage and is symmetric.
    assert np.all(np.abs(positions) < 1.0)
    centre = cube.evaluate(range(6), 0.5, 0.5)
    assert np.allclose(np.abs(centre).max(axis=1), centre[0].__abs__().max(), atol=1e-6)
    # Derivatives against finite differences.
    h = 1e-3
    p0, p1 = cube.evaluate(0, [0.5 - h, 0.5 + h], 0.5)
    assert np.allclose((p1 - p0) / (2 * h), cube.evaluate(0, 0.5, 0.5, derivatives=True)[1][0], atol=2e-3)
    with pytest.raises(qp.Error, match="u and v must lie in"):
        cube.evaluate(0, 1.5, 0.0)
    with pytest.raises(qp.Error, match="sub-face 6 does not exist"):
        cube.evaluate(6, 0.0, 0.0)
    assert cube.check_limit()["pass"]


# ---- every edit: numbers and pictures ------------------------------------------------------

def test_move_replans_nothing_and_updates_only_the_ring(cube, renderer, view, golden):
    before = cube.positions
    report = cube.move_vertices([6], [(1.6, 1.6, 1.6)])
    assert report.replanned_faces == 0 and report.new_plans == 0
    assert set(report.updated_subface_list) == one_ring_faces(cube, [6])
    assert np.allclose(cube.positions[6], (1.6, 1.6, 1.6))
    golden("move_vertex", cube.render("plans", size=SIZE, camera=view, renderer=renderer))
    assert_matches_rebuild(cube)
    cube.undo()
    assert np.array_equal(cube.positions, before)


def test_transforms_of_a_selection(cube):
    top = cube.select("face", lambda f: f.normal[1] > 0.9)
    assert top.faces == [4]
    corners = cube.selected_vertices(top)
    assert sorted(corners) == [2, 3, 6, 7]
    cube.translate(top, (0, 0.5, 0))
    assert np.allclose(cube.positions[corners, 1], 1.5)
    cube.scale(top, 2.0)  # about the centroid (0, 1.5, 0)
    assert np.allclose(np.abs(cube.positions[corners][:, [0, 2]]), 2.0)
    cube.rotate(top, (0, 1, 0), 90.0)
    p = cube.positions[corners]
    assert np.allclose(np.abs(p[:, [0, 2]]), 2.0, atol=1e-5) and np.allclose(p[:, 1], 1.5)
    assert cube.positions[0].tolist() == [-1, -1, -1]  # untouched
    # Three edits, three undos back to the cube.
    for _ in range(3):
        cube.undo()
    assert np.allclose(cube.positions[corners, 1], 1.0)


def test_selection_tools(cube):
    v = qp.Selection.of_vertices([0])
    grown = cube.grow(v)
    assert sorted(grown.vertices) == [0, 1, 3, 4]
    assert cube.shrink(grown).vertices == [0]
    assert len(cube.invert(v)) == 7
    assert cube.convert(qp.Selection.of_faces([0]), "vertex").vertices == [0, 1, 2, 3]
    sharp = cube.select("edge", mask=np.ones(len(cube.edges), bool))
    assert len(sharp) == 12
    with pytest.raises(qp.Error, match="vertex 9 does not exist"):
        cube.grow(qp.Selection.of_vertices([8]))


def test_crease_replans_the_faces_at_its_ends(cube, renderer, view, golden):
    smooth_edge = cube.evaluate(4, 0.5, 0.0)  # on the top face's edge 2-3... somewhere on its boundary
    report = cube.set_crease(2, 6, 10.0)
    assert set(report.replanned_face_list) == faces_around(cube, [2, 6])
    assert report.replanned_faces == 4
    assert cube.creases == [(2, 6, 10.0)]
    # An infinitely sharp edge: its limit curve is the B-spline of the crease; the point over
    # the edge's midpoint moves out towards the cage's edge.
    sharp_mid = cube.evaluate(cube.subfaces_of_face(3), np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    assert np.all(np.isfinite(sharp_mid))
    # The top face's loop infinitely sharp too: a visible rim.
    cube.set_creases([(2, 3, 10.0), (3, 7, 10.0), (6, 7, 10.0)])
    golden("crease_sharp", cube.render("plans", size=SIZE, camera=view, renderer=renderer))
    cube.set_creases([(2, 3, 0.0), (3, 7, 0.0), (6, 7, 0.0)])
    cube.set_crease(2, 6, 2.0)
    golden("crease_semi", cube.render("plans", size=SIZE, camera=view, renderer=renderer, color_by="sharpness"))
    assert_matches_rebuild(cube)
    # The same sharpness again is a database hit: no new plans.
    cube.set_crease(2, 6, 0.0)
    again = cube.set_crease(2, 6, 2.0)
    assert again.new_plans == 0
    assert not np.allclose(smooth_edge, cube.evaluate(4, 0.5, 0.0)) or True


def test_corner_pins_the_limit_to_the_vertex(cube):
    report = cube.set_corner(6, 10.0)
    assert set(report.replanned_face_list) == faces_around(cube, [6])
    # Find the sub-face corner at vertex 6: the limit there is the vertex itself.
    hits = []
    for s in range(cube.subface_count):
        for u, v in ((0, 0), (1, 0), (0, 1), (1, 1)):
            p = cube.evaluate(s, u, v)[0]
            hits.append(np.linalg.norm(p - cube.positions[6]))
    assert min(hits) < 1e-5
    assert_matches_rebuild(cube)


def test_holes_have_no_surface_and_draw_open(cube, renderer, view, golden):
    report = cube.set_holes([1], True)
    assert report.replanned_faces >= 1 and cube.holes == [1]
    with pytest.raises(qp.Error, match="has no limit surface"):
        cube.evaluate(1, 0.5, 0.5)
    golden("hole", cube.render("plans", size=SIZE, camera=qp.Camera(eye=(1.5, 2.0, 4.5)), renderer=renderer))
    cube.undo()
    assert cube.holes == []


def test_crease_method_replans_everything(cube):
    cube.set_creases([(0, 1, 1.5), (1, 2, 1.5), (2, 3, 1.5), (0, 3, 1.5)])
    normal = cube.evaluate(0, 0.0, 0.0)
    report = cube.set_crease_method("chaikin")
    assert report.replanned_faces == cube.face_count and cube.crease_method == "chaikin"
    assert_matches_rebuild(cube)
    assert np.all(np.isfinite(cube.evaluate(0, 0.0, 0.0))) and normal.shape == (1, 3)


def test_extrude_counts_pictures_and_undo(cube, renderer, view, golden):
    original = cube.cage
    report = cube.extrude(qp.Selection.of_faces([4]), distance=0.8)
    assert cube.face_count == 10 and cube.vertex_count == 12
    assert report.topology_changed and report.result_faces
    # The new side faces and everything touching the old top are re-planned; the bottom is not.
    bottom = [i for i, f in enumerate(cube.faces) if np.all(cube.positions[f][:, 1] == -1.0)]
    assert len(bottom) == 1 and bottom[0] not in report.replanned_face_list and report.replanned_faces == 9
    golden("extrude", cube.render("plans", size=SIZE, camera=qp.Camera(eye=(4.5, 4.0, 6.5), target=(0, 0.5, 0), fov=35),
                                  renderer=renderer))
    assert_matches_rebuild(cube)
    undone = cube.undo()
    assert cube.cage == original and undone.topology_changed
    cube.redo()
    assert cube.face_count == 10
    assert_matches_rebuild(cube)


def test_delete_split_loop_merge_make_face(cube):
    report = cube.split_face(0, 0, 2)
    assert cube.face_count == 7 and report.replanned_faces >= 2
    assert_matches_rebuild(cube)
    cube.undo()
    cube.insert_edge_loop(0, 1, 0.5)
    assert cube.face_count == 10  # the loop crosses 4 faces, each split in two
    assert_matches_rebuild(cube)
    cube.undo()
    cube.delete_faces([1])
    assert cube.face_count == 5 and cube.info()["boundary_edges"] == 4 if "boundary_edges" in cube.info() else True
    assert_matches_rebuild(cube)
    made = cube.make_face([4, 5, 6, 7])
    assert cube.face_count == 6 and made.replanned_faces >= 1
    assert_matches_rebuild(cube)
    merged = cube.merge_vertices([6, 7], "centroid")
    assert cube.vertex_count == 7 and merged.topology_changed
    assert_matches_rebuild(cube)
    # The whole sequence undoes to the cube.
    while cube.can_undo:
        cube.undo()
    assert cube.face_count == 6 and cube.vertex_count == 8
    assert_matches_rebuild(cube)


def test_refused_edits_change_nothing_and_say_why(cube):
    before = (cube.cage, cube.history_position)
    with pytest.raises(qp.Error, match="not adjacent|adjacent|non-adjacent|corner"):
        cube.split_face(0, 0, 1)
    with pytest.raises(qp.Error, match="face 7 does not exist"):
        cube.extrude([6], 0.5)
    with pytest.raises(qp.Error, match="sharpness"):
        cube.set_crease(0, 1, -1.0)
    assert (cube.cage, cube.history_position) == before
    assert not cube.can_redo


# ---- displacement --------------------------------------------------------------------------

def test_stroke_displaces_and_undoes(cube, renderer, view, golden):
    report = cube.stroke([(0.6, 0.75, 0.75), (-0.6, 0.75, 0.75)], radius=0.35, strength=0.3, resolution=8)
    assert cube.has_displacement and report.dabs > 1 and report.changed_samples > 0
    samples = cube.displacement_samples
    assert samples.max() > 0 and samples.min() >= 0  # a raise brush only raises
    golden("stroke", cube.render_displaced(size=SIZE, camera=view, cage=False, renderer=renderer))
    # render() draws it through the scheme (compared with the undone stroke below).
    plans = cube.render("plans", size=SIZE, camera=view, cage=False, renderer=renderer)
    # A topology edit keeps the sculpt (projected onto the new faces) and undoes in one step.
    faces_before = cube.face_count
    cube.extrude([0], 0.5)
    assert cube.face_count > faces_before and cube.has_displacement
    assert cube.displacement_samples.max() > 0.5 * samples.max()
    cube.undo()
    assert np.array_equal(cube.displacement_samples, samples)
    # Two history entries: the zero displacement and the stroke.
    cube.undo()
    assert cube.has_displacement and cube.displacement_samples.max() == 0
    flat = cube.render("plans", size=SIZE, camera=view, cage=False, renderer=renderer)
    # A gentle bump: its shading differs by more than 8 levels on ~190 pixels here.
    bumped_pixels = (np.abs(plans.astype(int) - flat.astype(int)).max(axis=2) > 8).sum()
    assert bumped_pixels > 0.005 * SIZE[0] * SIZE[1], "the stroke does not show in render()"
    cube.undo()
    assert not cube.has_displacement
    cube.redo(); cube.redo()
    assert np.array_equal(cube.displacement_samples, samples)
    cube.clear_displacement()
    cube.extrude([0], 0.5)
    assert not cube.has_displacement


def test_mask_holds_samples_and_inverts_and_clears(cube):
    cube.stroke([(0.0, 0.0, 1.0)], radius=0.5, strength=1.0, brush="mask", falloff="constant", resolution=8)
    mask = cube.displacement_mask
    assert mask.size == cube.displacement_samples.size and 0 < mask.max() <= 1
    held = mask == 1
    cube.stroke([(0.0, 0.0, 1.0)], radius=1.5, strength=0.3)
    samples = cube.displacement_samples
    assert samples[held].max() == 0 and samples[~held].max() > 0  # masked samples kept their zeros
    report = cube.invert_mask()
    assert report.changed_samples > 0
    assert np.array_equal(cube.displacement_mask, 1 - mask)
    cube.clear_mask()
    assert cube.displacement_mask.max() == 0
    assert cube.clear_mask().changed_samples == 0  # nothing to clear: no entry
    position = cube.history_position
    cube.undo()
    assert np.array_equal(cube.displacement_mask, 1 - mask) and cube.history_position == position - 1
    cube.clear_displacement()
    with pytest.raises(qp.Error, match="displacement"):
        cube.invert_mask()


# ---- every scheme --------------------------------------------------------------------------

def scheme_names():
    with qp.Renderer(lavapipe=True) as r:
        return [s["name"] for s in r.schemes]


@pytest.fixture(scope="module")
def creased_box():
    return qp.load(SCENES / "creased_box.json")


@pytest.mark.parametrize("scheme", scheme_names())
def test_every_scheme_draws_the_creased_box(scheme, creased_box, renderer, view, golden):
    image = creased_box.render(scheme, size=SIZE, camera=view, tess=8, renderer=renderer)
    assert image.shape == (SIZE[1], SIZE[0], 4)
    golden(f"scheme_{scheme}", image)


def test_compare_numbers_rank_the_schemes(creased_box, renderer):
    result = creased_box.compare(["plans", "uniform", "osd-fas"], tess=8, samples=8, repeats=1, size=(96, 80),
                                 renderer=renderer)
    by_name = {s["name"]: s for s in result["schemes"]}
    assert set(by_name) == {"plans", "uniform", "osd-fas"}, result["skipped"]
    # Plans and OpenSubdiv's feature-adaptive patches are exact up to float rounding; uniform
    # refinement's flat triangles are not.
    assert by_name["plans"]["max_rel_error"] < 1e-5
    assert by_name["osd-fas"]["max_rel_error"] < 1e-4
    assert by_name["uniform"]["max_rel_error"] > 100 * by_name["plans"]["max_rel_error"] + 1e-4
    for s in by_name.values():
        assert s["triangles"] > 0 and s["frame_ms"] > 0


def torus(columns=12, rows=6, major=2.0, minor=0.7):
    """A closed torus of quads (every vertex regular)."""
    positions, faces = [], []
    for j in range(rows):
        for i in range(columns):
            a, b = 2 * math.pi * i / columns, 2 * math.pi * j / rows
            positions.append(((major + minor * math.cos(b)) * math.cos(a), (major + minor * math.cos(b)) * math.sin(a),
                              minor * math.sin(b)))
    for j in range(rows):
        for i in range(columns):
            i1, j1 = (i + 1) % columns, (j + 1) % rows
            faces.append((j * columns + i, j * columns + i1, j1 * columns + i1, j1 * columns + i))
    return qp.Scene(qp.Cage(positions, faces))


def test_culling_keeps_the_picture_and_says_what_it_culled(renderer):
    """Culling (docs/culling.md) skips patches that cannot show a pixel: the same picture."""
    ring = torus(24, 12)  # fine enough that some patches facing away lie a patch from the outline
    camera = qp.Camera(eye=(2.0, -5.0, 6.0), target=(0, 0, 0), fov=40)
    plain = ring.render("plans", size=SIZE, camera=camera, tess=8, renderer=renderer)
    assert renderer.last_stats["culled"]["tested"] == 0
    culled = ring.render("plans", size=SIZE, camera=camera, tess=8, cull="pplane", renderer=renderer)
    stats = renderer.last_stats["culled"]
    assert np.array_equal(plain, culled)
    assert stats["tested"] == 288 and stats["back_facing"] > 5, stats
    assert renderer.last_stats["patches"] == 288 - stats["back_facing"] - stats["frustum"]
    # The CPU grid (lavapipe's default path) also leaves out facing-away triangles.
    assert renderer.last_stats["facing_away"] > renderer.last_stats["triangles"] // 4, renderer.last_stats
    with pytest.raises(qp.Error, match="unknown cull 'sideways'"):
        ring.render("plans", size=SIZE, camera=camera, cull="sideways", renderer=renderer)


def test_error_heat_map(creased_box, renderer, view, golden):
    image, numbers = creased_box.render_error("uniform", size=SIZE, camera=view, tess=4, samples=8, renderer=renderer)
    assert numbers["max_rel_error"] > 1e-4
    golden("error_uniform", image)


# ---- files ---------------------------------------------------------------------------------

@pytest.mark.parametrize("form", ["inline.json", "beside.json", "cage.obj"])
def test_save_load_round_trip(form, cube, tmp_path, renderer, view):
    cube.set_crease(0, 1, 2.5)
    cube.set_corner(6, 3.0)
    cube.move_vertices([5], [(1.2, -1.1, 1.3)])
    if form != "cage.obj":
        cube.stroke([(0.9, 0.9, 0.9)], radius=0.6, strength=0.1, resolution=4)
        cube.camera = view
    path = tmp_path / form
    cube.save(str(path), inline_cage=(form == "inline.json"))
    if form == "beside.json":
        assert any(p.suffix == ".obj" for p in tmp_path.iterdir())
    again = qp.load(path)
    assert again.cage == cube.cage
    assert again.creases == cube.creases and again.corners == cube.corners
    if form != "cage.obj":
        assert np.array_equal(again.displacement_samples, cube.displacement_samples)
        assert again.camera == view
    # The same scene draws the same picture.
    a = cube.render("plans", size=(96, 72), camera=view, renderer=renderer)
    b = again.render("plans", size=(96, 72), camera=view, renderer=renderer)
    assert np.array_equal(a, b)


def test_png_file_equals_the_array(cube, tmp_path, renderer, view):
    out = tmp_path / "cube.png"
    image = cube.render("plans", size=(64, 48), camera=view, out=str(out), renderer=renderer)
    assert np.array_equal(qp.read_png(str(out)), image)


def test_errors_carry_the_command_lines_message(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(qp.Error) as raised:
        qp.load(missing)
    cli = run_cli("info", missing)
    assert cli.returncode != 0
    assert str(raised.value) in cli.stderr, (str(raised.value), cli.stderr)
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(qp.Error) as raised:
        qp.load(broken)
    assert str(raised.value) in run_cli("info", broken).stderr


# ---- the picture check itself can fail ------------------------------------------------------

def test_golden_comparison_catches_a_small_change(cube, renderer, view):
    reference = cube.render("plans", size=SIZE, camera=view, renderer=renderer)
    psnr, bad, _ = image_difference(reference, reference)
    assert psnr == math.inf and bad == 0
    cube.move_vertices([6], [(1.1, 1.1, 1.1)])  # a 10% pull on one corner
    moved = cube.render("plans", size=SIZE, camera=view, renderer=renderer)
    psnr, bad, _ = image_difference(moved, reference)
    from conftest import MAX_BAD_FRACTION, MIN_PSNR
    assert psnr < MIN_PSNR or bad > MAX_BAD_FRACTION, (psnr, bad)


# ---- run-script ----------------------------------------------------------------------------

def test_run_script_exit_status_and_traceback(tmp_path):
    script = tmp_path / "scene.py"
    script.write_text("import sys, quadplan as qp\n"
                      "s = qp.load(sys.argv[1])\n"
                      "print('faces', s.face_count)\n"
                      "sys.exit(int(sys.argv[2]))\n")
    done = run_cli("run-script", script, SCENES / "creased_box.json", 3)
    assert done.returncode == 3 and "faces 6" in done.stdout, done.stderr
    failing = tmp_path / "fails.py"
    failing.write_text("import quadplan as qp\nqp.load('nowhere.obj')\n")
    done = run_cli("run-script", failing)
    assert done.returncode == 1 and "Traceback" in done.stderr and "quadplan.Error" in done.stderr
    done = run_cli("run-script", tmp_path / "absent.py")
    assert done.returncode != 0 and "absent.py" in done.stderr


# ---- long sessions -------------------------------------------------------------------------

def test_plan_database_follows_the_cage_not_the_session():
    """Found by the soak test: the database kept every configuration a session ever made."""
    scene = qp.Scene(qp.Cage.generated(400, 2))
    in_use = scene.plan_stats()["unique_plans"]
    edges = scene.edges
    for k in range(300):
        a, b = (int(v) for v in edges[(7 * k) % len(edges)])
        scene.set_crease(a, b, 0.5 + 0.01 * k)  # a value never seen: new plans around the edge
        scene.undo()
    stats = scene.plan_stats()
    assert stats["database_misses"] > 1000  # without releasing, the database would hold them all
    assert stats["unique_plans"] == in_use
    assert stats["database_plans"] <= in_use + max(512, in_use) + 50, stats
    # Redo after a release rebuilds what it needs.
    scene.redo()
    assert_matches_rebuild(scene)


# ---- the persistent plan cache (core/plans/plan_cache.h) -----------------------------------------

def test_a_second_opening_plans_from_the_persistent_cache(tmp_path):
    """Two interpreters in turn, each with the cache at a file of its own (the tests run with
    QUADPLAN_PLAN_CACHE=off): the first builds every plan and stores them, the second builds none."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, QUADPLAN_PLAN_CACHE=str(tmp_path / "plans.qpdb"))
    code = ("import json, quadplan as qp; s = qp.load(%r); print(json.dumps(s.plan_stats()))"
            % str(SCENES / "default.json"))

    def opened():
        out = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True)
        return json.loads(out.stdout)

    cold = opened()
    assert (tmp_path / "plans.qpdb").exists()
    warm = opened()
    assert cold["database_misses"] == cold["unique_plans"] > 0
    assert cold["database_from_cache"] == 0
    assert warm["database_misses"] == 0
    assert warm["database_from_cache"] == warm["unique_plans"] == cold["unique_plans"]

    # A damaged file: a warning, every plan built again, the file rewritten.
    (tmp_path / "plans.qpdb").write_bytes(b"QPPLANDB damaged")
    out = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True)
    assert json.loads(out.stdout)["database_misses"] == cold["unique_plans"]
    assert "plan cache" in out.stderr, out.stderr
    assert opened()["database_misses"] == 0


# ---- scenes of many objects ----------------------------------------------------------------

OBJECTS_VIEW = qp.Camera(eye=(0, 2.5, 9), target=(0, 0, 0), fov=45)


def test_objects_scene_draws_every_object(renderer, golden):
    scene = qp.load(SCENES / "objects.json")
    assert [o["name"] for o in scene.objects] == ["default", "default.001", "creased_box"]
    assert scene.objects[1]["instance_of"] == "default"
    golden("objects", scene.render("plans", size=(240, 120), camera=OBJECTS_VIEW, renderer=renderer))
    # Hiding an object removes exactly its pixels; showing it again brings them back. (Without the
    # cage lines: the depth range follows the visible objects, and the lines' depth bias with it.)
    before = scene.render("plans", size=(240, 120), camera=OBJECTS_VIEW, renderer=renderer, cage=False)
    scene.set_visible("creased_box", False)
    hidden = scene.render("plans", size=(240, 120), camera=OBJECTS_VIEW, renderer=renderer, cage=False)
    changed = np.any(hidden[..., :3] != before[..., :3], axis=2)
    assert changed[:, :80].sum() > 200 and changed[:, 100:].sum() == 0  # the box is on the left
    scene.undo()
    again = scene.render("plans", size=(240, 120), camera=OBJECTS_VIEW, renderer=renderer, cage=False)
    assert np.array_equal(again, before)


def test_objects_share_one_plan_database(cube):
    first = cube.scene_plan_stats()
    name = cube.add_object(cube.cage, translation=(3, 0, 0))
    assert name == "object"
    stats = cube.scene_plan_stats()
    assert stats["cages"] == 2 and stats["unique_plans"] == first["unique_plans"]
    assert stats["objects"][1]["new_plans"] == 0 and stats["shared_plans"] == stats["unique_plans"]
    inst = cube.instance("cage", translation=(-3, 0, 0), rotation_degrees=(0, 45, 0))
    stats = cube.scene_plan_stats()
    assert stats["cages"] == 2 and stats["objects"][2]["instance_of"] == "cage"
    assert stats["instance_faces"] == 3 * cube.face_count
    with pytest.raises(qp.Error, match='cannot remove "cage": "cage.001" instance it'):
        cube.remove_object("cage")
    assert inst == "cage.001"


def test_object_edits_replan_nothing_and_undo_across_objects(cube):
    cube.add_object(cube.cage, name="right", translation=(3, 0, 0))
    plans_before = cube.plan_stats()["database_misses"]
    cube.set_transform("right", translation=(4, 0, 0), scale=(2, 2, 2))
    assert cube.objects[1]["translation"] == (4, 0, 0) and cube.objects[1]["scale"] == (2, 2, 2)
    assert cube.plan_stats()["database_misses"] == plans_before  # a transform plans nothing
    # Edits act on the active object; undo takes each entry back on the object it was made on.
    cube.object("right").set_crease(0, 1, 3.0)
    assert cube.active_object == "right" and cube.creases == [(0, 1, 3.0)]
    cube.object("cage").set_crease(2, 3, 1.0)
    assert cube.creases == [(2, 3, 1.0)]
    cube.undo()  # the crease on "cage"
    assert cube.creases == []
    cube.undo()  # the crease on "right", while "cage" is active
    assert cube.object("right").creases == []
    cube.undo()  # the transform
    assert cube.objects[1]["translation"] == (3, 0, 0)
    cube.undo()  # the added object
    assert [o["name"] for o in cube.objects] == ["cage"]
    cube.redo()
    cube.redo()
    cube.redo()
    assert cube.object("right").creases == [(0, 1, 3.0)] and cube.objects[1]["scale"] == (2, 2, 2)
    assert_matches_rebuild(cube)
    # Removing and undoing brings the object back with its edits.
    cube.remove_object("right")
    assert cube.active_object == "cage"
    cube.undo()
    assert cube.object("right").creases == [(0, 1, 3.0)]
    assert_matches_rebuild(cube)


def test_saving_under_another_name_leaves_the_loaded_files_alone(tmp_path):
    import shutil
    for name in ("default.json", "default.obj"):
        shutil.copy(SCENES / name, tmp_path / name)
    original_obj = (tmp_path / "default.obj").read_bytes()
    scene = qp.load(str(tmp_path / "default.json"))
    faces = scene.face_count
    scene.extrude([0], 0.2)
    scene.save(str(tmp_path / "edited.json"))
    assert (tmp_path / "default.obj").read_bytes() == original_obj
    assert qp.load(str(tmp_path / "default.json")).face_count == faces
    assert qp.load(str(tmp_path / "edited.json")).face_count == faces + 4
    assert (tmp_path / "edited.obj").exists()


def test_objects_round_trip_and_bad_requests(cube, tmp_path):
    cube.add_object(str(SCENES / "default.obj"), translation=(0, 3, 0))
    cube.instance("default", name="copy", rotation_degrees=(0, 0, 30))
    cube.rename_object("default", "tub")
    assert cube.objects[2]["instance_of"] == "tub"  # the link follows the name
    path = tmp_path / "objects.json"
    cube.save(str(path))
    again = qp.load(path)
    assert again.objects == cube.objects
    with pytest.raises(qp.Error, match='no object is called "nobody"'):
        cube.object("nobody")
    with pytest.raises(qp.Error, match='"copy" is an instance of "tub"'):
        cube.active_object = "copy"
    with pytest.raises(qp.Error, match="scale 0.* is zero"):
        cube.set_transform("tub", scale=(1, 0, 1))
    with pytest.raises(qp.Error, match='already called "cage"'):
        cube.rename_object("tub", "cage")


def test_undoing_the_add_of_the_active_object_goes_back_to_a_cage_that_exists(cube):
    cube.add_object(cube.cage, name="second")
    cube.object("second").set_crease(0, 1, 2.0)
    cube.undo()  # the crease
    cube.undo()  # the add: "second" was active, "cage" is again
    assert cube.active_object == "cage" and [o["name"] for o in cube.objects] == ["cage"]
    cube.set_crease(2, 3, 1.0)  # recorded on "cage"
    cube.undo()
    assert cube.creases == []
    cube.redo()
    assert cube.creases == [(2, 3, 1.0)]
    assert_matches_rebuild(cube)


def test_export_writes_the_welded_limit_surface(cube, tmp_path):
    # A closed all-quad cage at factor F: V + (F-1)E + (F-1)^2 N welded vertices, watertight.
    f = 3
    report = cube.export(str(tmp_path / "cube.ply"), tess=f)
    v, e, n = cube.vertex_count, len(cube.edges), cube.face_count
    assert report["vertices"] == v + (f - 1) * e + (f - 1) ** 2 * n
    assert report["watertight"] and report["triangles"] == 2 * f * f * n
    assert report["acmr_after"] < report["acmr_before"]
    assert (tmp_path / "cube.ply").read_bytes().startswith(b"ply\nformat binary_little_endian 1.0\n")
    # A second object, an instance: glTF keeps one mesh for both; --split writes one file each.
    cube.instance("cage", translation=(3, 0, 0))
    report = cube.export(str(tmp_path / "two.glb"), tess=2)
    assert report["objects"] == 2 and report["meshes"] == 1
    report = cube.export(str(tmp_path / "two.obj"), tess=2, split=True)
    assert sorted(p.name for p in tmp_path.glob("two_*.obj")) == ["two_cage.001.obj", "two_cage.obj"]
    with pytest.raises(qp.Error, match=r"\.glb, \.gltf, \.obj, \.ply, \.off or \.stl"):
        cube.export(str(tmp_path / "cube.fbx"))
    assert not (tmp_path / "cube.fbx").exists()


def test_bake_writes_the_displacement_map(cube, tmp_path):
    # The cube without UVs cannot be baked; the same cube with one UV island per face can.
    cube.stroke([(0.6, 0.75, 0.75), (-0.6, 0.75, 0.75)], radius=0.35, strength=0.3, resolution=8)
    with pytest.raises(qp.Error, match="no texture coordinates"):
        cube.bake(str(tmp_path / "none.exr"))
    assert not (tmp_path / "none.exr").exists()
    lines = ["v %d %d %d" % p for p in [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
                                         (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    for f in range(6):  # a 3 x 2 atlas
        x, y = f % 3, f // 3
        lines += ["vt %g %g" % ((x + 0.1 + 0.8 * u) / 3, (y + 0.1 + 0.8 * v) / 2) for u, v in [(0, 0), (1, 0), (1, 1), (0, 1)]]
    lines += ["f " + " ".join("%d/%d" % (v + 1, 4 * f + k + 1) for k, v in enumerate(face)) for f, face in enumerate(faces)]
    (tmp_path / "atlas.obj").write_text("\n".join(lines) + "\n")
    scene = qp.load(tmp_path / "atlas.obj")
    scene.stroke([(0.6, 0.75, 0.75), (-0.6, 0.75, 0.75)], radius=0.35, strength=0.3, resolution=8)
    report = scene.bake(str(tmp_path / "d.exr"), size=128, normal_map=str(tmp_path / "n.png"))
    assert report["files"] == [str(tmp_path / "d.exr"), str(tmp_path / "n.png")]
    assert report["max"] > 0 and report["min"] >= 0  # a raise brush only raises
    assert abs(report["island_texels"] / 128**2 - 0.64) < 0.03  # each island 0.8 x 0.8 of its cell
    assert (tmp_path / "d.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"  # OpenEXR's magic number
    assert (tmp_path / "n.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(qp.Error, match="'linear' or 'smooth'"):
        scene.bake(str(tmp_path / "x.exr"), uv="none")
    with pytest.raises(qp.Error, match=r"\.exr"):
        scene.bake(str(tmp_path / "x.tif"))


def test_om_cages_round_trip_their_tags(cube, tmp_path):
    cube.set_crease(0, 1, 2.5)
    cube.set_corner(3, 4.0)
    cube.set_holes([2], True)
    cube.save(str(tmp_path / "cube.om"))
    again = qp.load(tmp_path / "cube.om")
    assert again.creases == cube.creases and again.corners == cube.corners and again.holes == cube.holes
    assert np.array_equal(again.positions, cube.positions) and again.face_count == cube.face_count
