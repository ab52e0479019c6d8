"""The Mitsuba tests: they need ``mitsuba`` and ``drjit`` (``pip install
omnee[mitsuba]``) and a JIT variant whose backend works (``llvm_ad_rgb``:
Dr.Jit's LLVM backend, with ``DRJIT_LIBLLVM_PATH`` pointing at LLVM ≥ 16).
Where ``OMNEE_MITSUBA_REQUIRED`` is set (``ci.sh`` here sets it), a
missing Mitsuba fails the run instead of skipping it."""

import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

VARIANT = os.environ.get("OMNEE_MITSUBA_VARIANT", "llvm_ad_rgb")


def _mitsuba():
    try:
        import mitsuba as mi

        mi.set_variant(VARIANT)
        return mi
    except Exception as e:  # ImportError, or a variant whose backend does not load
        message = f"Mitsuba with the variant {VARIANT} is not usable here: {e}"
        if os.environ.get("OMNEE_MITSUBA_REQUIRED"):
            raise RuntimeError(message) from e
        pytest.skip(message)


@pytest.fixture(scope="session")
def mi():
    """``mitsuba`` with the test variant set and ``omnee_volpath`` registered."""
    m = _mitsuba()
    import omnee.mitsuba  # noqa: F401  (registers the integrator)

    return m
