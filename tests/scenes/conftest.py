"""Fixtures of the scene tests (docs/python.md, "Scene tests").

Pictures are compared with golden PNGs in tests/scenes/golden/ (small, drawn by Mesa's lavapipe
with Vulkan validation on, so any machine gets the same pixels up to rasteriser rounding).
A comparison passes when both hold:
  - PSNR against the golden >= MIN_PSNR dB (over RGB), and
  - at most MAX_BAD_FRACTION of the pixels differ by more than BAD_PIXEL_DELTA in a channel.
On failure NAME.actual.png and NAME.diff.png (|difference| x 4, red where a pixel is "bad") are
written to the output directory ($QUADPLAN_SCENE_TEST_OUTPUT, else a pytest temporary
directory), and the message gives their paths and the numbers.

New or intentionally changed pictures: run with --update-goldens (or
QUADPLAN_UPDATE_GOLDENS=1), LOOK at the written PNGs, and commit them. A missing golden is a
failure, never a skip.
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import quadplan as qp

HERE = pathlib.Path(__file__).resolve().parent
GOLDEN_DIR = HERE / "golden"
REPO = HERE.parent.parent
SCENES = REPO / "scenes"

MIN_PSNR = 38.0
BAD_PIXEL_DELTA = 24
MAX_BAD_FRACTION = 0.002


def pytest_addoption(parser):
    parser.addoption("--update-goldens", action="store_true", help="write the golden PNGs instead of comparing")


@pytest.fixture(scope="session")
def renderer():
    """Lavapipe with validation: any validation message fails the render that caused it."""
    with qp.Renderer(validation=True, lavapipe=True) as r:
        yield r


@pytest.fixture(scope="session")
def output_dir(tmp_path_factory):
    chosen = os.environ.get("QUADPLAN_SCENE_TEST_OUTPUT")
    path = pathlib.Path(chosen) if chosen else tmp_path_factory.mktemp("scene-output")
    path.mkdir(parents=True, exist_ok=True)
    return path


def image_difference(actual, golden):
    """(psnr in dB, fraction of bad pixels, difference picture) of two (H, W, 4) uint8 images."""
    a = actual[..., :3].astype(np.int32)
    g = golden[..., :3].astype(np.int32)
    delta = np.abs(a - g)
    mse = float(np.mean(delta.astype(np.float64) ** 2))
    psnr = float("inf") if mse == 0 else 10.0 * np.log10(255.0 ** 2 / mse)
    bad = delta.max(axis=2) > BAD_PIXEL_DELTA
    diff = np.clip(delta * 4, 0, 255).astype(np.uint8)
    diff[bad] = (255, 0, 0)
    rgba = np.dstack([diff, np.full(bad.shape, 255, np.uint8)])
    return psnr, float(bad.mean()), rgba


@pytest.fixture
def golden(request, output_dir):
    """golden(name, image): compares a rendered (H, W, 4) array with tests/scenes/golden/name.png."""
    update = request.config.getoption("--update-goldens") or os.environ.get("QUADPLAN_UPDATE_GOLDENS") == "1"

    def check(name, image, min_psnr=MIN_PSNR, max_bad_fraction=MAX_BAD_FRACTION):
        path = GOLDEN_DIR / f"{name}.png"
        if update:
            GOLDEN_DIR.mkdir(exist_ok=True)
            qp.write_png(str(path), image)
            return
        if not path.exists():
            actual = output_dir / f"{name}.actual.png"
            qp.write_png(str(actual), image)
            pytest.fail(f"no golden image {path}; the picture is in {actual}: look at it, then run with --update-goldens")
        expected = qp.read_png(str(path))
        if expected.shape != image.shape:
            actual = output_dir / f"{name}.actual.png"
            qp.write_png(str(actual), image)
            pytest.fail(f"{name}: size {image.shape[1]}x{image.shape[0]} but the golden is "
                        f"{expected.shape[1]}x{expected.shape[0]} (actual picture: {actual})")
        psnr, bad, diff = image_difference(image, expected)
        if psnr < min_psnr or bad > max_bad_fraction:
            actual, diff_path = output_dir / f"{name}.actual.png", output_dir / f"{name}.diff.png"
            qp.write_png(str(actual), image)
            qp.write_png(str(diff_path), diff)
            pytest.fail(f"{name} differs from {path}: PSNR {psnr:.1f} dB (needs >= {min_psnr}), "
                        f"{100 * bad:.2f}% of pixels off by more than {BAD_PIXEL_DELTA} (allowed {100 * max_bad_fraction:.2f}%); "
                        f"actual: {actual}, difference: {diff_path}")
        return psnr, bad

    return check


@pytest.fixture
def cube():
    """A unit cube scene (8 vertices, 6 quads), planned to depth 6."""
    positions = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return qp.Scene(qp.Cage(positions, faces))


@pytest.fixture
def view():
    """The camera every golden picture is drawn from (unless a test says otherwise)."""
    return qp.Camera(eye=(3.2, 2.4, 4.0), target=(0, 0, 0), fov=35)


def quadplan_binary():
    return os.environ.get("QUADPLAN_BINARY", str(REPO / "build" / "bin" / "quadplan"))


def run_cli(*args):
    return subprocess.run([quadplan_binary(), *map(str, args)], capture_output=True, text=True)
