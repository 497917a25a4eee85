"""Issue 28 finding 7 (loader part): an arrays.npz holding an array beyond its model is refused before it is inflated."""

from __future__ import annotations

import io
import json
import resource
import shutil
import zipfile

import numpy as np
import pytest

from gaitml.errors import ModelError
from gaitml.models import load_model
from gaitml.models._persist import sha256_file
from tests.conftest import ROOT


def _with_arrays(tmp_path, extra: dict[str, tuple[tuple[int, ...], str]]):
    """A copy of the demo model whose arrays.npz gains members (zeros of the given shape, compressed), sha256 updated."""
    dst = tmp_path / "model"
    shutil.copytree(ROOT / "models" / "demo", dst)
    npz = dst / "arrays.npz"
    with zipfile.ZipFile(npz, "a", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, (shape, dtype) in extra.items():
            header = io.BytesIO()
            np.lib.format.write_array_header_1_0(header, {"descr": np.dtype(dtype).str, "fortran_order": False, "shape": shape})
            n = int(np.prod(shape)) * np.dtype(dtype).itemsize
            with zf.open(f"{name}.npy", "w", force_zip64=True) as fh:
                fh.write(header.getvalue())
                block = bytes(1 << 20)
                for _ in range(n >> 20):
                    fh.write(block)
                fh.write(bytes(n & ((1 << 20) - 1)))
    info = json.loads((dst / "model.json").read_text())
    info["files"]["arrays.npz"] = sha256_file(npz)
    (dst / "model.json").write_text(json.dumps(info, indent=2))
    return dst


def test_a_huge_array_of_zeros_is_refused_before_decompressing(tmp_path):
    model = _with_arrays(tmp_path, {"domain__bomb": ((100_000_000,), "<f4")})  # 400 MB of zeros, ~0.4 MB compressed
    assert (model / "arrays.npz").stat().st_size < 10_000_000
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(ModelError, match="declares an array of shape"):
        load_model(model)
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    assert grown_mb < 200  # nothing was inflated


def test_a_member_larger_than_its_header_is_refused(tmp_path):
    dst = tmp_path / "model"
    shutil.copytree(ROOT / "models" / "demo", dst)
    npz = dst / "arrays.npz"
    with zipfile.ZipFile(npz, "a") as zf:
        header = io.BytesIO()
        np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10,)})
        zf.writestr("domain__liar.npy", header.getvalue() + bytes(8 * 1000))
    info = json.loads((dst / "model.json").read_text())
    info["files"]["arrays.npz"] = sha256_file(npz)
    (dst / "model.json").write_text(json.dumps(info, indent=2))
    with pytest.raises(ModelError, match="holds .* bytes but its header declares"):
        load_model(dst)


def test_the_shipped_models_load():
    for name in ("demo", "demo-acc"):
        assert load_model(ROOT / "models" / name).labels
