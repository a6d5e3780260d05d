"""A fresh Python process on an empty kernel cache, for the tests of the first call (``test_jit_warm_up``,
``test_interpreted``): it runs a program with this checkout's package and prints a JSON line last."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np

from splinecraft.capture import _jit

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(_jit.__file__))))

#: The bitmap the programs trace (also as code, for them): a rectangle with a rectangular hole.
HOLED_RECTANGLE = """
mask = np.zeros((40, 60), bool)
mask[8:32, 10:50] = True
mask[14:26, 20:30] = False
"""


def holed_rectangle():
    namespace = {"np": np}
    exec(HOLED_RECTANGLE, namespace)
    return namespace["mask"]


def run_cold(code, cache, timeout=900, **environment):
    """Run ``code`` in a fresh interpreter whose numba cache is the empty folder ``cache``, with ``environment``
    added (``None`` removes a variable); returns the JSON of its last line of output."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache),
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    for name, value in environment.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=timeout,
                          check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])
