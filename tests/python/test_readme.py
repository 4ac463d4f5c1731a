"""The README's Python block runs as is and prints what it says."""

import os
import re
import subprocess
import sys


def test_the_readme_block_runs(source_dir):
    with open(os.path.join(source_dir, "README.md")) as f:
        text = f.read()
    section = text[text.index("## Using Quack from Python"):]
    block = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    run = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True,
                         check=False)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("ball at [")
    # The ball fell from y = 5 onto the ground (top at 0.5) within the second.
    y = float(lines[0].strip("]").split()[-1])
    assert 0.9 < y < 5.0
    assert re.match(r"distance \d\.\d{3} m, normal \(", lines[1])
    assert lines[2] == "(100000,) (100000, 2)"
