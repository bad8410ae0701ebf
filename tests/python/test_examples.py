"""The examples in examples/python run (tiny settings) and write their PNG figures."""
import os
import subprocess
import sys

from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "examples" / "python"


def run_example(script, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run([sys.executable, str(EXAMPLES / script), *args], env=env, capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return result.stdout


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10000


def test_lobes_example(tmp_path):
    out = tmp_path / "lobes.png"
    stdout = run_example("lobes.py", "--photons", "20000", "--rows", "12", "--reference-spp", "2",
                         "--threads", "2", "--out", str(out))
    assert f"wrote {out}" in stdout
    assert_png(out)


def test_equal_time_example(tmp_path):
    out = tmp_path / "equal_time.png"
    stdout = run_example("equal_time.py", "--scene", str(SOURCE_DIR / "bench/scenes/thin.xml"), "--width", "32",
                         "--height", "24", "--time", "0.3", "--reference-time", "0.5", "--threads", "2",
                         "--guided", "photons=20000 direction=product", "--out", str(out))
    assert "volpath:" in stdout and "guided_volpath" in stdout
    assert_png(out)
