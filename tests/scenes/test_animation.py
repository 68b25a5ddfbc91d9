"""Cage animation through the Python module (docs/python.md, "Animation"): frames re-plan nothing
and equal the cage planned from scratch at that frame, moves and topology edits on an animated
cage key it and carry its keys, undo and redo, the scene file round trip, OBJ sequences, and
refusals that name the frame and change nothing.
"""
import json
import math

import numpy as np
import pytest

import quadplan as qp

CUBE = np.array([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)],
                dtype=np.float32)
FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
TOP = 4  # the face at y = 1


def twisted(frame):
    """The cube twisted about y by 10 degrees per frame, more towards the top."""
    angle = np.radians(10.0 * frame) * (CUBE[:, 1] + 1.0)
    out = CUBE.copy()
    out[:, 0] = CUBE[:, 0] * np.cos(angle) - CUBE[:, 2] * np.sin(angle)
    out[:, 2] = CUBE[:, 0] * np.sin(angle) + CUBE[:, 2] * np.cos(angle)
    return out


def shifted(frame):
    """The cube moved along x by 0.25 per frame after frame 1."""
    out = CUBE.copy()
    out[:, 0] += 0.25 * (frame - 1)
    return out


def linear(pose, keys, frame):
    """Where linear interpolation of `pose` keyed at `keys` has every vertex at `frame`."""
    if frame <= keys[0]:
        return pose(keys[0])
    if frame >= keys[-1]:
        return pose(keys[-1])
    i = max(k for k in range(len(keys) - 1) if keys[k] <= frame)
    t = (frame - keys[i]) / (keys[i + 1] - keys[i])
    return (1 - t) * pose(keys[i]) + t * pose(keys[i + 1])


def animated(tmp_path, pose=twisted, keys=(1, 5, 9)):
    """A scene file of the cube with every vertex keyed at `keys`, loaded."""
    scene = {"format": "quadplan-scene", "version": 2, "objects": [{
        "name": "cube", "cage": {"positions": CUBE.tolist(), "faces": FACES},
        "animation": {"keys": [{"frame": k, "vertices": list(range(8)), "positions": pose(k).tolist()} for k in keys]}}]}
    path = tmp_path / "animated.json"
    path.write_text(json.dumps(scene))
    return qp.load(path)


def limit_points(scene):
    s, u, v = np.meshgrid(np.arange(scene.subface_count), np.linspace(0, 1, 5), np.linspace(0, 1, 5), indexing="ij")
    return scene.evaluate(s.ravel(), u.ravel(), v.ravel())


def write_obj(path, positions, faces=FACES):
    lines = [f"v {x} {y} {z}" for x, y, z in positions] + ["f " + " ".join(str(v + 1) for v in f) for f in faces]
    path.write_text("\n".join(lines) + "\n")


def test_frames_replan_nothing_and_equal_the_cage_planned_at_that_frame(tmp_path):
    scene = animated(tmp_path)
    assert scene.is_animated and scene.frames == (1, 9) and scene.fps == 24
    assert scene.frame == 1 and np.allclose(scene.positions, twisted(1), atol=1e-6)  # opens at its first frame
    assert scene.keyed_frames == [1, 5, 9] and scene.interpolation == "linear"
    assert np.array_equal(scene.rest_positions, CUBE)
    misses = scene.plan_stats()["database_misses"]
    for frame in (3, 5.5, 9, 12, 2, 1):
        shown = scene.positions
        report = scene.set_frame(frame)
        expected = linear(twisted, (1, 5, 9), frame)
        assert report.name == f"Frame {frame:g}" and scene.frame == frame
        assert report.replanned_faces == 0 and report.new_plans == 0
        assert report.updated_subfaces == (0 if np.array_equal(expected, shown) else scene.subface_count)  # 12 holds 9
        assert np.allclose(scene.positions, expected, atol=1e-5)
        fresh = qp.Scene(qp.Cage(expected, FACES))
        assert np.allclose(limit_points(scene), limit_points(fresh), atol=1e-5), frame
    assert scene.plan_stats()["database_misses"] == misses
    assert scene.differences_from_rebuild() == []
    assert len(scene.history) == 0  # frames are not edits


def test_a_cage_without_keys_edits_as_before(tmp_path):
    scene = qp.Scene(qp.Cage(CUBE, FACES))
    assert not scene.is_animated and scene.frames == (1, 1) and scene.frame == 1 and scene.keyed_frames == []
    assert scene.move_vertices([6], [(1.5, 1.5, 1.5)]).name == "Move"
    assert scene.set_frame(4).updated_subfaces == 0
    assert np.array_equal(scene.rest_positions, scene.positions)
    assert scene.positions[6].tolist() == [1.5, 1.5, 1.5]


def test_moves_key_the_current_frame_and_interpolate(tmp_path):
    scene = animated(tmp_path, keys=(1, 9))
    scene.set_frame(9)
    target = twisted(9)[6] + (0, 1, 0)
    report = scene.move_vertices([6], [target])
    assert report.name == "Move, key at frame 9" and report.replanned_faces == 0
    assert np.allclose(scene.positions[6], target)
    # A drag's later steps (merge=True) replace its entry: one undo takes the drag back.
    entries = len(scene.history)
    scene.move_vertices([6], [target + (0, 0.5, 0)], merge=True)
    scene.move_vertices([6], [target], merge=True)
    assert len(scene.history) == entries
    scene.undo()
    assert np.allclose(scene.positions[6], twisted(9)[6])
    scene.redo()
    assert np.allclose(scene.positions[6], target)
    scene.set_frame(5)
    assert np.allclose(scene.positions[6], (twisted(1)[6] + target) / 2, atol=1e-5)
    assert np.allclose(scene.positions[:6], linear(twisted, (1, 9), 5)[:6], atol=1e-5)
    # A transform at frame 5 keys the vertices it moves there; the others keep their tracks.
    scene.set_frame(3)
    at3 = scene.positions
    scene.set_frame(5)
    before = scene.positions
    report = scene.translate([0, 1], (0, 0, 0.5))
    assert report.name == "Move, key at frame 5" and scene.keyed_frames == [1, 5, 9]
    scene.set_frame(3)
    assert np.allclose(scene.positions[0], (twisted(1)[0] + before[0] + (0, 0, 0.5)) / 2, atol=1e-5)
    keyed = scene.positions
    scene.undo()  # the translate, undone at frame 3: vertex 0 is back on its 1-9 track there
    assert np.allclose(scene.positions, at3)
    assert scene.keyed_frames == [1, 9]
    scene.redo()
    assert np.allclose(scene.positions, keyed) and scene.keyed_frames == [1, 5, 9]
    # Keys without a move: inserted where the animation is, so nothing moves at any frame.
    scene.set_key(frame=7)
    assert scene.keyed_frames == [1, 5, 7, 9] and np.allclose(scene.positions, keyed)
    assert scene.remove_keys(7).name == "Remove keys at frame 7" and scene.keyed_frames == [1, 5, 9]
    scene.set_key([2], [(0, 3, 0)], frame=12)
    assert scene.frames == (1, 12) and np.allclose(scene.positions, keyed, atol=1e-6)  # frame 3 is before it
    scene.set_frame(12)
    assert scene.positions[2].tolist() == [0, 3, 0]
    scene.set_frame(2.5)
    with pytest.raises(qp.Error, match="keys go on whole frames and the scene shows frame 2.5"):
        scene.move_vertices([0], [(0, 0, 0)])
    assert scene.differences_from_rebuild() == []


def test_topology_edits_carry_the_keys_to_every_frame(tmp_path):
    scene = animated(tmp_path, pose=shifted, keys=(1, 9))
    scene.set_frame(5)
    report = scene.extrude([TOP], 0.5)
    assert report.name == "Extrude" and scene.vertex_count == 12
    at5 = scene.positions
    # The cube slides along x: the extruded vertices slide with it.
    for frame in (1, 9, 3):
        scene.set_frame(frame)
        assert scene.set_frame(frame).replanned_faces == 0
        assert np.allclose(scene.positions, at5 + (0.25 * (frame - 5), 0, 0), atol=1e-5), frame
        assert scene.differences_from_rebuild() == []
    scene.undo()  # at frame 3
    assert scene.vertex_count == 8 and np.allclose(scene.positions, shifted(3), atol=1e-5)
    assert np.array_equal(scene.rest_positions, CUBE)
    scene.redo()
    assert scene.vertex_count == 12 and np.allclose(scene.positions, at5 + (-0.5, 0, 0), atol=1e-5)
    # An edge loop: its vertices keep to their edges at every frame.
    scene.insert_edge_loop(0, 1, 0.5)
    scene.set_frame(9)
    assert np.allclose(scene.positions[:12], at5 + (1.0, 0, 0), atol=1e-5)
    assert scene.differences_from_rebuild() == []
    scene.undo()
    scene.undo()
    assert scene.vertex_count == 8 and np.allclose(scene.positions, shifted(9), atol=1e-5)


def test_round_trip_and_undo_of_transform_keys_interpolation_and_timeline(tmp_path):
    scene = animated(tmp_path)
    scene.set_frame(5)
    scene.move_vertices([6], [(0, 2, 0)])
    scene.set_transform_key("cube", 1, translation=(0, 0, 0))
    scene.set_transform_key("cube", 9, translation=(3, 0, 0), rotation_degrees=(0, 90, 0))
    assert scene.objects[0]["translation"] == (1.5, 0, 0)  # shown at frame 5
    scene.set_transform("cube", scale=(2, 2, 2))  # a keyed transform is keyed at the current frame
    assert scene.history[-1].name == "Transform key cube at frame 5"
    scene.set_interpolation("catmull-rom")
    scene.set_timeline(1, 12, 30)
    assert scene.frames == (1, 12) and scene.fps == 30 and scene.frame == 5
    scene.set_frame(4)
    path = tmp_path / "saved.json"
    scene.save(str(path))
    saved = json.loads(path.read_text())
    assert np.allclose(saved["objects"][0]["cage"]["positions"], CUBE)  # the rest, not frame 4
    assert saved["timeline"] == {"fps": 30.0, "first_frame": 1, "last_frame": 12}
    again = qp.load(path)
    assert again.frame == 1 and again.frames == (1, 12) and again.fps == 30 and again.interpolation == "catmull-rom"
    assert again.keyed_frames == scene.keyed_frames and np.array_equal(again.rest_positions, scene.rest_positions)
    for frame in (4, 1, 6.5, 9, 12):
        scene.set_frame(frame)
        again.set_frame(frame)
        assert np.array_equal(again.positions, scene.positions), frame
        assert again.objects == scene.objects, frame
    # Undo, newest first (between keys, where the interpolation shows).
    scene.set_frame(3)
    scene.undo()
    assert scene.frames == (1, 9) and scene.fps == 24
    catmull_rom = scene.positions
    scene.undo()
    assert scene.interpolation == "linear" and not np.allclose(scene.positions, catmull_rom)
    scene.undo()
    assert scene.objects[0]["scale"] == (1, 1, 1)
    scene.undo()
    scene.undo()
    assert scene.objects[0]["translation"] == (0, 0, 0) and scene.objects[0]["rotation_degrees"] == (0, 0, 0)
    scene.undo()
    assert np.allclose(scene.positions, linear(twisted, (1, 5, 9), 3), atol=1e-5)


def test_objects_taken_out_come_back_at_the_current_frame(tmp_path):
    scene = animated(tmp_path)
    scene.add_object(qp.Cage(CUBE, FACES), name="still", translation=(4, 0, 0))
    scene.remove_object("cube")
    scene.set_frame(9)
    scene.undo()  # the removal
    assert scene.object("cube").keyed_frames == [1, 5, 9]
    assert np.allclose(scene.positions, twisted(9), atol=1e-5) and np.array_equal(scene.rest_positions, CUBE)
    assert np.array_equal(scene.object("still").positions, CUBE)
    # Each object is keyed on its own: a move of "still" keys nothing.
    assert scene.move_vertices([0], [(-2, -1, -1)]).name == "Move"
    assert scene.set_frame(3).replanned_faces == 0 and scene.object("still").positions[0].tolist() == [-2, -1, -1]


def test_a_sequence_becomes_keys_and_bad_ones_change_nothing(tmp_path):
    walk = tmp_path / "walk"
    walk.mkdir()
    for k in range(1, 5):
        write_obj(walk / f"frame_{k:04d}.obj", CUBE * (1 + k / 10))
    scene = qp.Scene(qp.Cage(CUBE, FACES))
    scene.load_sequence(str(walk / "frame_*.obj"))
    assert scene.keyed_frames == [1, 2, 3, 4] and scene.frames == (1, 4) and scene.frame == 1
    assert np.allclose(scene.positions, CUBE * 1.1)
    scene.set_frame(3)
    assert np.allclose(scene.positions, CUBE * 1.3)
    path = tmp_path / "walking.json"
    scene.save(str(path))
    assert json.loads(path.read_text())["objects"][0]["animation"]["sequence"] == "walk/frame_*.obj"
    again = qp.load(path)
    again.set_frame(3)
    assert np.array_equal(again.positions, scene.positions)
    scene.undo()
    assert scene.keyed_frames == [] and np.array_equal(scene.positions, CUBE)
    scene.redo()

    bad = tmp_path / "bad"
    bad.mkdir()
    for k in (1, 2, 4):
        write_obj(bad / f"f_{k}.obj", CUBE)
    before = (scene.positions, scene.keyed_frames, len(scene.history), scene.frame)

    def unchanged():
        assert np.array_equal(scene.positions, before[0]) and scene.keyed_frames == before[1]
        assert len(scene.history) == before[2] and scene.frame == before[3]

    with pytest.raises(qp.Error, match="is missing frame 3"):
        scene.load_sequence(str(bad / "f_*.obj"))
    unchanged()
    write_obj(bad / "f_3.obj", np.vstack([CUBE, [(0, 0, 0)]]), FACES + [(8, 0, 1, 2)])
    with pytest.raises(qp.Error, match=r"sequence frame 3: .*f_3.obj: the frame has 9 vertices, the cage 8"):
        scene.load_sequence(str(bad / "f_*.obj"))
    unchanged()
    for frame in (math.nan, math.inf):
        with pytest.raises(ValueError, match="finite"):
            scene.set_frame(frame)
        unchanged()
    with pytest.raises(qp.Error, match='"cage" has no vertex keys at frame 7 \\(its keys are at frames 1, 2, 3, 4\\)'):
        scene.remove_keys(7)
    with pytest.raises(qp.Error, match="3 positions for 2 vertices"):
        scene.set_key([0, 1], [(0, 0, 0)] * 3)
    with pytest.raises(qp.Error, match="the last frame 1 comes before the first, 5"):
        scene.set_timeline(5, 1)
    unchanged()


def test_transform_keys_are_removed_undoably_and_a_missing_one_is_named():
    scene = qp.Scene(qp.Cage(CUBE, FACES))
    scene.set_transform_key("cage", 1, translation=(0, 0, 0))
    scene.set_transform_key("cage", 5, translation=(4, 0, 0))
    scene.set_transform_key("cage", 9, translation=(4, 4, 0))
    scene.set_frame(7)
    assert scene.objects[0]["translation"] == (4, 2, 0)
    entries = len(scene.history)
    scene.remove_transform_key("cage", 5)
    assert len(scene.history) == entries + 1 and scene.history[-1].name == "Remove transform key cage at frame 5"
    assert scene.objects[0]["translation"] == (3, 3, 0)  # now 1 to 9: three quarters of the way at 7
    scene.undo()
    assert scene.objects[0]["translation"] == (4, 2, 0)
    scene.redo()
    assert scene.objects[0]["translation"] == (3, 3, 0)

    before = (scene.objects, len(scene.history))
    with pytest.raises(qp.Error, match=r'"cage" has no transform key at frame 5 \(its transform keys are at frames 1, 9\)'):
        scene.remove_transform_key("cage", 5)
    with pytest.raises(qp.Error, match=r'no object is called "car" \(the scene has cage\)'):
        scene.remove_transform_key("car", 1)
    with pytest.raises(qp.Error, match="frame 2000000000 is out of range"):
        scene.remove_transform_key("cage", 2000000000)
    assert (scene.objects, len(scene.history)) == before

    # Frame 9's key alone holds from frame 7 on; without keys left the object keeps what it shows.
    scene.remove_transform_key("cage", 1)
    assert scene.is_animated and scene.objects[0]["translation"] == (4, 4, 0)
    scene.remove_transform_key("cage", 9)
    assert not scene.is_animated and scene.objects[0]["translation"] == (4, 4, 0)
    scene.set_frame(1)
    assert scene.objects[0]["translation"] == (4, 4, 0)
    with pytest.raises(qp.Error, match=r'"cage" has no transform key at frame 9 \(it has no transform keys\)'):
        scene.remove_transform_key("cage", 9)
    scene.undo()
    assert scene.is_animated and scene.objects[0]["translation"] == (4, 4, 0)
    scene.undo()  # frame 1's key back, shown at frame 1
    assert scene.objects[0]["translation"] == (0, 0, 0)
