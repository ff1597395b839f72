# pytest setup for the Python module's tests (tests/README.md): the module
# is imported from the build tree (ctest sets PYTHONPATH=BUILD/python), the
# CLI for comparisons is $NULD_BIN.
import os
import shutil
import subprocess

import pytest


@pytest.fixture(scope="session")
def nuld_bin():
    path = os.environ.get("NULD_BIN") or shutil.which("nuld")
    if not path:
        pytest.skip("the nuld program is not known (set NULD_BIN)")
    return path


# A tiny trained model, for the entry points that take one.
@pytest.fixture(scope="module")
def model(tmp_path_factory, nuld_bin):
    path = str(tmp_path_factory.mktemp("model") / "tiny.nuldnet")
    subprocess.run([nuld_bin, "train", "--target", "uniform", "--n", "8", "--hidden", "16",
                    "--steps", "2", "-q", "-o", path], check=True, capture_output=True)
    return path
