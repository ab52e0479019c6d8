"""A call's memory is its output arrays: inputs are read in place and
outputs written in place, without temporaries. Measured as the growth of
the peak resident set (VmHWM) over one call, in a fresh process."""

import json
import subprocess
import sys

import pytest

CHILD = r"""
import json, resource, sys
import numpy as np, omnee
n, dtype, kind = int(sys.argv[1]), np.dtype(sys.argv[2]), sys.argv[3]
rng = np.random.default_rng(1)
def uniform(k):
    a = np.empty((n, k), dtype)
    rng.random(out=a, dtype=dtype)
    return a
x0 = (0.0, 0.0, 1.0)
if kind == "rows":
    x2 = uniform(3)
    x2 -= np.asarray((0.0, 0.0, 1.0), dtype)
else:
    x2 = (0.0, 0.0, 0.0)
t = (omnee.Mis if kind == "mis" else omnee.Omnee)(x0, x2, "hg:0.9")
u = uniform(t.dimension)
small = 1000
(omnee.Omnee(x0, x2[:small], "hg:0.9").sample(u[:small, :3]) if kind == "rows" else t.sample(u[:small]))
def peak():
    # VmHWM: the peak of this process's own memory (ru_maxrss would start
    # from the parent's resident set at the fork).
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
before = peak()
s = t.sample(u)
after = peak()
print(json.dumps([after - before, sum(a.nbytes for a in s)]))
"""


@pytest.mark.parametrize("dtype", ["float32", "float64"])
@pytest.mark.parametrize("kind", ["one", "rows", "mis"])
def test_peak_memory_of_a_call_is_its_outputs(dtype, kind):
    n = 2_000_000
    out = subprocess.run([sys.executable, "-c", CHILD, str(n), dtype, kind],
                         check=True, capture_output=True, text=True).stdout
    grew, outputs = json.loads(out)
    assert grew <= 1.2 * outputs, f"peak grew by {grew / 1e6:.1f} MB for {outputs / 1e6:.1f} MB of outputs"
