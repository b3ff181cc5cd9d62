"""DIPY's tensors as DIPY hands them over (issue 28.1): DTI from DIPY's TensorModel on the
small_64D data, drawn from ``lower_triangular()`` (DIPY's order, a strided view) with
``tensor_order="dipy"`` and from ``quadratic_form`` ((..., 3, 3) matrices), gives exactly
the depth of the same tensors reordered here into glyphcast's order; the same six values
without ``tensor_order`` are refused, not drawn as needles."""
import nibabel as nib
import numpy as np
import pytest
from dipy.core.gradients import gradient_table
from dipy.reconst.dti import TensorModel

import glyphcast
from conftest import ROOT, assert_same_depth

# DIPY's lower_triangular order (xx, xy, yy, xz, yz, zz) to glyphcast's (xx, xy, xz, yy,
# yz, zz), spelled here from DIPY's documentation.
DIPY_TO_GLYPHCAST = [0, 1, 3, 2, 4, 5]
SIZE = dict(width=160, height=160)


DIPY_DATA = ROOT / "tests" / "data" / "dipy"


@pytest.fixture(scope="module")
def dipy_fit():
    dipy_data = DIPY_DATA
    image = nib.load(dipy_data / "small_64D.nii")
    data = np.asarray(image.dataobj, dtype=np.float64)
    bvals = np.loadtxt(dipy_data / "small_64D.bval")
    bvecs = np.loadtxt(dipy_data / "small_64D.bvec")
    if bvecs.shape[0] == 3:
        bvecs = bvecs.T
    gtab = gradient_table(bvals, bvecs=np.nan_to_num(bvecs))
    return TensorModel(gtab).fit(data), image.affine


def test_lower_triangular_and_quadratic_form_draw_the_reordered_tensors(dipy_fit):
    fit, affine = dipy_fit
    lower = fit.lower_triangular()
    assert not lower.flags.c_contiguous  # as DIPY returns it: a strided view
    reordered = np.ascontiguousarray(lower[..., DIPY_TO_GLYPHCAST])
    options = dict(order=2, glyph="ellipsoid", **SIZE)
    expected = glyphcast.render_tensor(reordered, affine, **options)
    covered = np.isfinite(expected.depth).sum()
    assert covered > 2000, covered
    from_lower = glyphcast.render_tensor(lower, affine, tensor_order="dipy", **options)
    assert_same_depth(from_lower.depth, expected.depth)
    assert np.array_equal(from_lower.rgba, expected.rgba)
    matrices = fit.quadratic_form
    assert matrices.shape[3:] == (3, 3)
    from_matrices = glyphcast.render_tensor(matrices, affine, **options)
    assert_same_depth(from_matrices.depth, expected.depth)
    # Named orders are case-insensitive; FSL's order is glyphcast's.
    fsl = glyphcast.render_tensor(reordered, affine, tensor_order="FSL", **options)
    assert_same_depth(fsl.depth, expected.depth)


def test_dipy_order_without_its_name_is_refused(dipy_fit):
    fit, affine = dipy_fit
    with pytest.raises(ValueError) as refused:
        glyphcast.render_tensor(fit.lower_triangular(), affine, order=2, glyph="ellipsoid")
    message = str(refused.value)
    assert message.startswith("coeffs: values: "), message
    assert "not positive definite" in message and "tensor_order=dipy" in message, message
    with pytest.raises(ValueError, match="tensor_order='lower': not one of"):
        glyphcast.render_tensor(fit.lower_triangular(), affine, order=2, tensor_order="lower")
    with pytest.raises(ValueError, match="no stored order"):
        glyphcast.render_tensor(fit.quadratic_form, affine, order=2, tensor_order="dipy")
    skewed = fit.quadratic_form.copy()
    skewed[5, 5, 5, 0, 1] += 1e-3
    with pytest.raises(ValueError, match=r"symmetric.*\(5, 5, 5\)"):
        glyphcast.render_tensor(skewed, affine, order=2)
    with pytest.raises(ValueError, match="tensor_order"):
        glyphcast.render_tensor(
            np.zeros((2, 2, 2, 15)), order=4, tensor_order="dipy"
        )
