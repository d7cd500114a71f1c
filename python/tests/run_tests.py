"""Runs the module's pytest suite for ctest; exits 77 (ctest's SKIP_RETURN_CODE) naming what is missing."""
import importlib.util
import sys
from pathlib import Path

missing = [name for name in ("numpy", "pytest") if importlib.util.find_spec(name) is None]
if missing:
    print(f"SKIPPED: {sys.executable} has no {' or '.join(missing)} "
          "(scripts/deps.sh installs python3-numpy and python3-pytest)")
    sys.exit(77)

import pytest  # noqa: E402 - only once it is known to be there

# No cache: the suite runs from the source tree, which it leaves as it was.
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", str(Path(__file__).resolve().parent), *sys.argv[1:]]))
