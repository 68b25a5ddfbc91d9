"""Soak test (issue 9): thousands of random valid edits on a ~2,000-face cage through the Python
interface, with resident memory watched and the incrementally kept plans checked against a
rebuild from scratch at the end.

    quadplan run-script tests/scenes/soak.py [--edits 10000] [--faces 2000] [--seed 1]
                                             [--warmup 0.2] [--report FILE.json]

Edits are drawn at random (fixed seed, so a failure replays): vertex moves and transforms,
edge creases, corners, holes, extrusions, face splits, face deletions, vertex merges, edge
loops, displacement strokes (carried across topology edits) and clearing them, undo and
redo. Topology edits are excursions: now and then (5% of the steps) the history jumps back to
before the oldest one still applied, so the cage keeps its size and character, and tags are
cleared about as often as set; what memory holds after warm-up is then the same kind of cage. The history gets a 32 MiB budget; warm-up ends when it is 90% full (and
--warmup of the edits are done): from then on the history drops as much as it records.
Resident memory is sampled every 50 edits; after warm-up, its level over the last third of the
samples (their median) must stay within 10% of its level over the first third. Medians, not
single samples: the allocator returns and takes pages in steps of a few MiB, which one sample at
the end of warm-up against the highest one after it read as growth (7.6 to 10.6% on runs without
a leak), while a leak raises the whole last third. Exit status 1 on any failure, with the reason.
"""
import argparse
import json
import os
import random
import sys
import tempfile
import time

import numpy as np

import quadplan as qp


def resident_bytes():
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


TOPOLOGY_ENTRIES = {"Extrude", "Delete faces", "Split face", "Merge vertices", "Edge loop", "Make face"}


class Soak:
    def __init__(self, scene, rng):
        self.scene = scene
        self.rng = rng
        self.start_faces = scene.face_count
        self.start_creases = len(scene.creases)
        self.start_corners = len(scene.corners)
        self.bbox = np.ptp(scene.positions, axis=0).max()
        self.counts = {}
        self.refused = {}

    # ---- helpers ------------------------------------------------------------------------
    def face(self):
        return self.rng.randrange(self.scene.face_count)

    def used_vertex(self):
        faces = self.scene.faces
        return self.rng.choice(faces[self.rng.randrange(len(faces))])

    def interior_edge(self):
        edges = self.scene.edges
        return tuple(int(v) for v in edges[self.rng.randrange(len(edges))])

    def record(self, name, report):
        self.counts[name] = self.counts.get(name, 0) + 1
        return report

    # ---- edits --------------------------------------------------------------------------
    def move(self):
        vertices = sorted({self.used_vertex() for _ in range(self.rng.randint(1, 4))})
        positions = self.scene.positions[vertices]
        offset = np.array([self.rng.uniform(-1, 1) for _ in range(3)], dtype=np.float32) * 0.01 * self.bbox
        return self.scene.move_vertices(vertices, positions + offset)

    def transform(self):
        vertex = self.used_vertex()
        selection = self.scene.grow(qp.Selection.of_vertices([vertex]))
        kind = self.rng.randrange(3)
        if kind == 0:
            return self.scene.translate(selection, [0.0, 0.005 * self.bbox, 0.0], space="local")
        if kind == 1:
            return self.scene.rotate(selection, [0, 0, 1], self.rng.uniform(-10, 10))
        return self.scene.scale(selection, self.rng.uniform(0.95, 1.05))

    def crease(self):
        # Tags stay near their starting number (clearing one as often as setting one, as an
        # artist's session does) and take a few values: the set of configurations in use then
        # stops growing, and memory can be judged.
        creases = self.scene.creases
        if len(creases) > self.start_creases and self.rng.random() < 0.7:
            a, b, _ = self.rng.choice(creases)
            return self.scene.set_crease(a, b, 0.0)
        a, b = self.interior_edge()
        return self.scene.set_crease(a, b, self.rng.choice([1.0, 2.5, 10.0]))

    def corner(self):
        corners = self.scene.corners
        if len(corners) > self.start_corners and self.rng.random() < 0.7:
            return self.scene.set_corner(self.rng.choice(corners)[0], 0.0)
        return self.scene.set_corner(self.used_vertex(), self.rng.choice([2.0, 10.0]))

    def hole(self):
        holes = self.scene.holes
        if holes and self.rng.random() < 0.6:
            return self.scene.set_holes([self.rng.choice(holes)], False)
        return self.scene.set_holes([self.face()], True)

    def grow_topology(self):
        # With displacement the edit carries it to the new faces (issue 19 part 3).
        kind = self.rng.randrange(3)
        if kind == 0:
            return self.scene.extrude([self.face()], self.rng.uniform(-0.02, 0.05) * self.bbox)
        if kind == 1:
            for _ in range(20):
                f = self.face()
                face = self.scene.faces[f]
                if len(face) >= 4:
                    k = self.rng.randrange(len(face))
                    return self.scene.split_face(f, face[k], face[(k + 2) % len(face)])
            return self.scene.extrude([self.face()], 0.01 * self.bbox)
        # Edge loops add a ring of faces: rarer, and only while there is room.
        a, b = self.interior_edge()
        return self.scene.insert_edge_loop(a, b, self.rng.uniform(0.2, 0.8))

    def shrink_topology(self):
        if self.rng.random() < 0.5:
            return self.scene.delete_faces([self.face()], remove_unused_vertices=True)
        # Merge the two ends of a short edge (collapses it).
        a, b = self.interior_edge()
        return self.scene.merge_vertices([a, b], "centroid")

    def stroke(self):
        f = self.face()
        centre = self.scene.positions[self.scene.faces[f]].mean(axis=0)
        direction = np.array([self.rng.uniform(-1, 1) for _ in range(3)], dtype=np.float32)
        path = [centre, centre + 0.03 * self.bbox * direction]
        brush = self.rng.choice(["raise", "lower", "smooth", "flatten", "erase"])
        return self.scene.stroke(path, radius=0.04 * self.bbox, strength=0.05 if brush in ("raise", "lower") else 0.5,
                                 brush=brush, resolution=4)

    def revert_topology(self):
        """Undoes back to before the oldest topology edit still applied (jump_to): topology edits
        are excursions, so the cage keeps its size and character over the whole run."""
        history = self.scene.history
        applied = [i for i in range(self.scene.history_position) if history[i].name in TOPOLOGY_ENTRIES]
        if not applied:
            return None
        return self.scene.jump_to(applied[0])

    def undo(self):
        return self.scene.undo() if self.scene.can_undo else None

    def redo(self):
        return self.scene.redo() if self.scene.can_redo else None

    def step(self):
        r = self.rng.random()
        if self.rng.random() < 0.05:
            r = 2.0  # revert the topology excursions
        crowded = self.scene.face_count > 1.15 * self.start_faces
        sparse = self.scene.face_count < 0.85 * self.start_faces
        if r < 0.25:
            name, edit = "move", self.move
        elif r < 0.32:
            name, edit = "transform", self.transform
        elif r < 0.44:
            name, edit = "crease", self.crease
        elif r < 0.49:
            name, edit = "corner", self.corner
        elif r < 0.52:
            name, edit = "hole", self.hole
        elif r < 0.60:
            name, edit = ("shrink_topology", self.shrink_topology) if crowded else ("grow_topology", self.grow_topology)
        elif r < 0.65:
            name, edit = ("grow_topology", self.grow_topology) if sparse else ("shrink_topology", self.shrink_topology)
        elif r < 0.75:
            name, edit = "stroke", self.stroke
        elif r < 0.90:
            name, edit = "undo", self.undo
        elif r < 1.0:
            name, edit = "redo", self.redo
        else:
            name, edit = "revert_topology", self.revert_topology
        try:
            report = edit()
        except qp.Error as error:
            # A random edit the editor refuses (a merge that would make a face degenerate, a
            # split of a face whose corners are adjacent...) must leave the scene as it was;
            # the final rebuild comparison checks that it did.
            self.refused[name] = self.refused.get(name, 0) + 1
            self.refused.setdefault("examples", {}).setdefault(name, str(error))
            return
        if report is not None:
            self.record(name, report)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--edits", type=int, default=10000)
    parser.add_argument("--faces", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--warmup", type=float, default=0.2, help="fraction of the edits before memory is watched")
    parser.add_argument("--tolerance", type=float, default=0.10, help="allowed growth of resident memory after warm-up")
    parser.add_argument("--history-budget-mib", type=float, default=32)
    parser.add_argument("--report", help="write the figures as JSON here")
    args = parser.parse_args()

    rng = random.Random(args.seed)
    scene = qp.Scene(qp.Cage.generated(args.faces, args.seed))
    scene.history_budget = int(args.history_budget_mib * (1 << 20))
    soak = Soak(scene, rng)
    warmup = int(args.edits * args.warmup)
    samples = []  # (edit, resident bytes, history bytes, faces)
    baseline, warm_at = None, None
    start = time.time()
    for i in range(args.edits):
        soak.step()
        if (i + 1) % 50 == 0 or i + 1 == args.edits:
            rss = resident_bytes()
            stats = scene.plan_stats()
            samples.append((i + 1, rss, scene.history_bytes, scene.face_count, stats["database_plans"], stats["unique_plans"]))
            # Warm-up ends once the history holds what its budget allows (from then on it drops
            # as much as it records) and the warm-up fraction has passed.
            if baseline is None and i + 1 >= warmup and scene.history_bytes >= 0.9 * scene.history_budget:
                baseline, warm_at = rss, i + 1
    elapsed = time.time() - start

    failures = []
    if baseline is None:
        print(f"FAIL: the history never reached its budget ({args.history_budget_mib} MiB) in {args.edits} edits: "
              "no warm-up end to measure from; run more edits or lower --history-budget-mib", file=sys.stderr)
        return 1
    after = [s[1] for s in samples if s[0] >= warm_at]
    peak = max(after)
    third = max(1, len(after) // 3)
    if len(after) < 6:
        print(f"FAIL: only {len(after)} memory samples after warm-up (edit {warm_at}): run more edits", file=sys.stderr)
        return 1
    early, late = float(np.median(after[:third])), float(np.median(after[-third:]))
    growth = late / early - 1.0
    if growth > args.tolerance:
        failures.append(f"resident memory grew {100 * growth:.1f}% after warm-up (median of the first third of the "
                        f"samples {early / 2**20:.1f} MiB -> last third {late / 2**20:.1f} MiB), more than {100 * args.tolerance:.0f}%")
    differences = scene.differences_from_rebuild()
    if differences:
        failures.append(f"{len(differences)} sub-faces differ from a rebuild, e.g. {differences[:3]}")
    # The displacement carried through every topology edit still fits the cage: the scene saves,
    # and loads back (which checks the layout against the cage) with the same samples.
    if scene.has_displacement:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "soaked.json")
            scene.save(path, inline_cage=True)
            again = qp.load(path)
            if not np.array_equal(again.displacement_samples, scene.displacement_samples):
                failures.append("the displacement saved after the soak loads back different")

    figures = {
        "edits": args.edits, "seed": args.seed, "start_faces": soak.start_faces, "end_faces": scene.face_count,
        "min_faces": min(s[3] for s in samples), "max_faces": max(s[3] for s in samples),
        "seconds": round(elapsed, 1), "edits_per_second": round(args.edits / elapsed, 1),
        "warm_after_edits": warm_at, "resident_after_warmup_mib": round(baseline / 2**20, 2), "resident_peak_after_warmup_mib": round(peak / 2**20, 2),
        "resident_early_median_mib": round(early / 2**20, 2), "resident_late_median_mib": round(late / 2**20, 2),
        "resident_end_mib": round(samples[-1][1] / 2**20, 2), "growth_percent": round(100 * growth, 2),
        "history_entries": len(scene.history), "history_mib": round(scene.history_bytes / 2**20, 2),
        "database_plans": scene.plan_stats()["database_plans"], "plans_in_use": scene.plan_stats()["unique_plans"],
        "creases": len(scene.creases), "corners": len(scene.corners), "holes": len(scene.holes),
        "displaced_at_end": scene.has_displacement, "counts": soak.counts,
        "refused": {k: v for k, v in soak.refused.items() if k != "examples"},
        "refused_examples": soak.refused.get("examples", {}), "rebuild_differences": len(differences),
        # edit, RSS MiB, history MiB, faces, plans held, plans in use
        "samples": [(s[0], round(s[1] / 2**20, 2), round(s[2] / 2**20, 2), s[3], s[4], s[5]) for s in samples],
    }
    summary = {k: v for k, v in figures.items() if k != "samples"}
    print(json.dumps(summary, indent=1))
    if args.report:
        with open(args.report, "w") as out:
            json.dump(figures, out, indent=1)
    for failure in failures:
        print("FAIL:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
