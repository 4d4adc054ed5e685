# Shared pieces of the Python tests: where the repository, the built command-line tool and the
# shared maps are, and helpers that run the tool and compare folders.
import os
import subprocess
from pathlib import Path
from typing import Dict, List

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUNDLED_MAP = ROOT / "data" / "normalmaps" / "pyramidwall_256.png"
# The real maps beside the checkout (../shared), when they are there.
SHARED_MAPS = ROOT.parent / "shared" / "data" / "normalmaps"


def cli_path() -> Path:
    return Path(os.environ.get("NDFMIP_CLI") or ROOT / "build" / "ndfmip")


@pytest.fixture
def cli() -> Path:
    path = cli_path()
    if not path.is_file() or not os.access(path, os.X_OK):
        pytest.skip(f"no ndfmip tool at {path} (set NDFMIP_CLI)")
    return path


def run_cli(cli: Path, *args: str) -> str:
    """Runs the tool; its stdout, or the test fails with its stderr."""
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def folder_bytes(folder: Path) -> Dict[str, bytes]:
    """Every file below `folder`: relative path -> bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def assert_same_folders(a: Path, b: Path) -> None:
    fa, fb = folder_bytes(a), folder_bytes(b)
    assert sorted(fa) == sorted(fb)
    different: List[str] = [name for name in fa if fa[name] != fb[name]]
    assert not different, f"files differ between {a} and {b}: {different}"
