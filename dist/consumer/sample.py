"""The installed omnee package used as a user would (dist/check.sh runs it
with the venv's interpreter, from outside the source tree): it must be the
package in site-packages with its compiled extension, sample, evaluate and
invert consistently, and estimate the once-scattered transfer within 4.5
standard errors of its quadrature reference."""

import pathlib
import sys

import numpy as np

import omnee

package = pathlib.Path(omnee.__file__).resolve().parent
extension = pathlib.Path(omnee._omnee.__file__).name
assert "site-packages" in package.parts, f"omnee imported from {package}, not site-packages"
assert extension.endswith(".abi3.so"), f"the extension is {extension}, not the stable ABI's"

u = np.random.default_rng(1).random((10_000, 3))
t = omnee.Omnee(x0=[0, 0, 1], x2=[0, 0, 0], phase=omnee.Phase("hg:0.9"))
s = t.sample(u)
assert s.valid.all(), "every draw of OMNEE over θ < π has a vertex"
assert np.allclose(t.pdf(s.x1), s.pdf, rtol=1e-9), "pdf(x1) differs from the sample's pdf"
assert np.allclose(t.invert(s.x1).u, u, atol=1e-9), "invert(sample(u)) differs from u"

e = omnee.estimate(x0=(0, 0, 1), x2=(0, 0, 0), phase="hg:0.9", sigma_s=0.5, sigma_t=0.55,
                   technique="omnee", samples=100_000, seed=1)
deviation = (e.mean - e.reference) / e.stderr
assert abs(deviation) <= 4.5, f"estimate {e.mean} is {deviation:.1f} standard errors off {e.reference}"

print(f"python {sys.version.split()[0]}, numpy {np.__version__}: omnee {omnee.__version__} "
      f"({extension}); estimate {e.mean:.6g} ± {e.stderr:.2g}, reference {e.reference:.6g}")
