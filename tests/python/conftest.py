# pytest setup for the Python module's tests (tests/README.md): the module
# is imported from the build tree (ctest sets PYTHONPATH=BUILD/python), the
# CLI for comparisons is $NULD_BIN.
import os
import shutil

import pytest


@pytest.fixture(scope="session")
def nuld_bin():
    path = os.environ.get("NULD_BIN") or shutil.which("nuld")
    if not path:
        pytest.skip("the nuld program is not known (set NULD_BIN)")
    return path
