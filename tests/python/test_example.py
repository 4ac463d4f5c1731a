"""examples/python/plot_paths.py runs a scene and writes a PNG of the bodies' paths and an
SVG of the world at the end (World.to_svg)."""

import os
import subprocess
import sys

import numpy as np


def test_the_example_plots_a_scene(source_dir, tmp_path):
    out = tmp_path / "paths.png"
    svg = tmp_path / "world.svg"
    script = os.path.join(source_dir, "examples", "python", "plot_paths.py")
    scene = os.path.join(source_dir, "scenes", "sensor.json")
    run = subprocess.run([sys.executable, script, scene, "--steps", "60", "--out", str(out),
                          "--svg", str(svg)], capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stderr
    picture = svg.read_text()
    assert picture.rstrip().endswith("</svg>") and "sensor.json after 60 steps" in picture
    # sensor.json rains 40 balls; the ground and the zone are static.
    assert "40 bodies, 60 steps" in run.stdout
    data = out.read_bytes()
    assert data.startswith(b"\x89PNG\r\n\x1a\n")
    import matplotlib.image
    image = matplotlib.image.imread(str(out))
    assert image.shape[:2] == (600, 800)
    # Something was drawn: the picture is not one flat colour.
    assert np.ptp(image[..., :3]) > 0.5


def test_the_example_refuses_a_bad_scene(source_dir, tmp_path):
    script = os.path.join(source_dir, "examples", "python", "plot_paths.py")
    run = subprocess.run([sys.executable, script, str(tmp_path / "none.json"), "--out",
                          str(tmp_path / "x.png"), "--svg", str(tmp_path / "x.svg")],
                         capture_output=True, text=True, check=False)
    assert run.returncode != 0
    assert "none.json" in run.stderr
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.svg").exists()
