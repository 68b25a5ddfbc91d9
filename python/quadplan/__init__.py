"""Quadplan's scripting interface (docs/python.md).

    import quadplan as qp
    scene = qp.load("scenes/creased_box.json")
    report = scene.extrude(qp.Selection.of_faces([0]), distance=0.3)
    print(report.replanned_faces)
    scene.render("plans", size=(400, 300), out="box.png")

Everything the editor can do to a cage is a Scene method that returns an EditReport and can be
undone; failures raise quadplan.Error with the command line's message. Renders go through the
scheme plugins on a headless Vulkan device (default_renderer()).
"""

import atexit as _atexit
import os as _os

import numpy as _np

from ._quadplan import (Cage, Camera, EditReport, Error, HistoryEntry, Renderer, Scene, Selection, Tessellation,
                        read_png, set_default_plugin_dir, write_png)
from . import _paths

__all__ = ["Cage", "Camera", "EditReport", "Error", "HistoryEntry", "Renderer", "Scene", "Selection", "Tessellation",
           "default_renderer", "load", "read_png", "schemes", "write_png"]

set_default_plugin_dir(_paths.plugin_dir)

_default_renderer = None


def default_renderer():
    """The Renderer scenes draw with when none is given, created on first use.

    $QUADPLAN_VALIDATE=1 turns Vulkan validation on (any message then raises quadplan.Error),
    $QUADPLAN_LAVAPIPE=1 picks Mesa's CPU driver (deterministic pictures), $QUADPLAN_VK_DEVICE a
    device by name, $QUADPLAN_PLUGIN_DIR the plugin directory.
    """
    global _default_renderer
    if _default_renderer is None:
        _default_renderer = Renderer(validation=_os.environ.get("QUADPLAN_VALIDATE") == "1",
                                     lavapipe=_os.environ.get("QUADPLAN_LAVAPIPE") == "1")
    return _default_renderer


@_atexit.register
def _close_default_renderer():
    # Before the interpreter unloads the extension and the plugins it holds.
    global _default_renderer
    if _default_renderer is not None:
        _default_renderer.close()
        _default_renderer = None


def load(path, depth=6):
    """Opens a scene (.json) or a bare cage (.obj, .ply, .off, .stl) and plans it to `depth`: a quadplan.Scene."""
    return Scene.load(str(path), depth)


def schemes(renderer=None):
    """The loaded scheme plugins as dicts (name, summary, path), as `quadplan schemes --json` lists them."""
    return (renderer or default_renderer()).schemes


class VertexView:
    """What Scene.select passes a predicate in vertex mode: index, position (x, y, z), corner
    sharpness and valence (edges at the vertex)."""
    __slots__ = ("index", "position", "sharpness", "valence")

    def __repr__(self):
        return f"<vertex {self.index} at {tuple(self.position)}>"


class EdgeView:
    """What Scene.select passes a predicate in edge mode: vertices (a, b), positions (2, 3),
    midpoint, sharpness, number of faces using it."""
    __slots__ = ("vertices", "positions", "midpoint", "sharpness", "face_count")

    def __repr__(self):
        return f"<edge {self.vertices}>"


class FaceView:
    """What Scene.select passes a predicate in face mode: index, vertices, positions (n, 3),
    centroid, unit normal (area-weighted; zero when degenerate), whether it is a hole."""
    __slots__ = ("index", "vertices", "positions", "centroid", "normal", "hole")

    def __repr__(self):
        return f"<face {self.index} {self.vertices}>"


def _select(self, mode="vertex", where=None, mask=None):
    """A Selection of the elements for which `where(view)` is true (a VertexView, EdgeView or
    FaceView per element), or whose entry in the boolean array `mask` is true (one per vertex,
    edge as listed by Scene.edges, or face).

        top = scene.select("vertex", lambda v: v.position[1] > 0.5)
        up = scene.select("face", lambda f: f.normal[1] > 0.9)
        sharp = scene.select("edge", mask=scene.edges[:, 0] < 4)
    """
    if (where is None) == (mask is None):
        raise Error("give either a predicate `where` or a boolean `mask`")
    positions = self.positions
    edges = self.edges
    if mode == "vertex":
        count = len(positions)
    elif mode == "edge":
        count = len(edges)
    elif mode == "face":
        count = self.face_count
    else:
        raise Error(f"unknown selection mode '{mode}'; use vertex, edge or face")
    if mask is not None:
        mask = _np.asarray(mask, dtype=bool)
        if mask.shape != (count,):
            raise Error(f"the mask must have one entry per {mode} ({count}), got shape {mask.shape}")
        chosen = _np.nonzero(mask)[0].tolist()
    else:
        chosen = [i for i, view in enumerate(_views(self, mode, positions, edges)) if where(view)]
    if mode == "vertex":
        return Selection.of_vertices(chosen)
    if mode == "face":
        return Selection.of_faces(chosen)
    return Selection.of_edges([tuple(edges[i]) for i in chosen])


def _views(scene, mode, positions, edges):
    if mode == "vertex":
        valence = _np.zeros(len(positions), dtype=int)
        for a, b in edges:
            valence[a] += 1
            valence[b] += 1
        corners = dict(scene.corners)
        for i, p in enumerate(positions):
            view = VertexView()
            view.index, view.position, view.sharpness, view.valence = i, p, corners.get(i, 0.0), int(valence[i])
            yield view
    elif mode == "edge":
        creases = {(a, b): s for a, b, s in scene.creases}
        uses = {}
        for face in scene.faces:
            for k, a in enumerate(face):
                b = face[(k + 1) % len(face)]
                key = (min(a, b), max(a, b))
                uses[key] = uses.get(key, 0) + 1
        for a, b in edges:
            view = EdgeView()
            key = (int(a), int(b))
            view.vertices, view.positions = key, positions[[a, b]]
            view.midpoint = view.positions.mean(axis=0)
            view.sharpness, view.face_count = creases.get(key, 0.0), uses.get(key, 0)
            yield view
    else:
        holes = set(scene.holes)
        for i, face in enumerate(scene.faces):
            view = FaceView()
            view.index, view.vertices, view.positions = i, face, positions[face]
            view.centroid = view.positions.mean(axis=0)
            # Newell's area vector of the polygon.
            p, q = view.positions, _np.roll(view.positions, -1, axis=0)
            normal = 0.5 * _np.cross(p, q).sum(axis=0)
            length = _np.linalg.norm(normal)
            view.normal = normal / length if length > 0 else normal
            view.hole = i in holes
            yield view


Scene.select = _select
