"""Bad input of every kind raises an exception with a one-line message naming what is wrong;
nothing crashes."""

import numpy as np
import pytest

import pointillist

X = np.arange(4, dtype=np.float32)


def raises(exc, message, **kw):
    args = dict(x=X, y=X, width=8, height=8)
    args.update(kw)
    with pytest.raises(exc) as info:
        pointillist.points(**args)
    text = str(info.value)
    assert "\n" not in text
    assert text == message


def test_mismatched_lengths():
    raises(ValueError, "y has 3 rows but x has 4; every column needs one row a point", y=X[:3])
    raises(ValueError, "size has 5 rows but x has 4; every column needs one row a point",
           size=np.ones(5))
    raises(ValueError, "color has 2 rows but x has 4; every column needs one row a point",
           color=np.ones(2, np.uint32))
    raises(ValueError, "z has 1 rows but x has 4; every column needs one row a point",
           z=np.zeros(1))


def test_nans_name_their_row():
    bad = np.array([0.0, 1.0, np.nan, np.nan])
    raises(ValueError, "x[2] is NaN", x=bad)
    raises(ValueError, "y[2] is NaN", y=bad.astype(np.float32))
    raises(ValueError, "z[2] is NaN", z=bad)
    raises(ValueError, "size[2] is NaN", size=bad)
    raises(ValueError, "size is NaN", size=float("nan"))
    big = np.zeros(300_000, np.float32)
    big[299_999] = np.nan
    raises(ValueError, "y[299999] is NaN", x=np.zeros(300_000), y=big)


def test_wrong_shapes():
    raises(ValueError, "x must be a 1-D array; got shape (2, 2)", x=X.reshape(2, 2))
    raises(ValueError, "y must be a 1-D array; got shape ()", y=np.float32(1.0))
    raises(ValueError, "color must be a D3DCOLOR, a 1-D array of D3DCOLORs or an (n, 4) RGBA "
           "array; got shape (4, 1, 1)", color=np.zeros((4, 1, 1), np.uint32))
    raises(TypeError, "color has dtype uint8 and shape (4, 3); expected uint32 D3DCOLORs (n,) "
           "or uint8 RGBA (n, 4)", color=np.zeros((4, 3), np.uint8))
    raises(ValueError, "texture must be an (height, width, 4) uint8 RGBA array; got dtype "
           "uint8 and shape (4, 4)", texture=np.zeros((4, 4), np.uint8))
    raises(ValueError, "texture must be an (height, width, 4) uint8 RGBA array; got dtype "
           "float32 and shape (2, 2, 4)", texture=np.zeros((2, 2, 4), np.float32))


def test_wrong_dtypes():
    raises(TypeError, "x has dtype <U1; expected real numbers (float32 and float64 are read "
           "in place)", x=np.array(["a", "b", "c", "d"]))
    raises(TypeError, "y has dtype complex128; expected real numbers (float32 and float64 are "
           "read in place)", y=X.astype(complex))
    raises(TypeError, "x has dtype object; expected real numbers (float32 and float64 are "
           "read in place)", x=np.array([1, None, 2, 3], dtype=object))
    raises(TypeError, "color has dtype float32 and shape (4,); expected uint32 D3DCOLORs (n,) "
           "or uint8 RGBA (n, 4)", color=X)
    raises(TypeError, "color must be a D3DCOLOR, an integer 0xAARRGGBB", color=1.5)
    raises(TypeError, "size is a bool; expected a number of pixels", size=True)
    raises(TypeError, "clear must be a D3DCOLOR, an integer 0xAARRGGBB", clear="black")


def test_values_out_of_range():
    raises(ValueError, "color 0x100000000 is outside 0..=0xFFFFFFFF (a D3DCOLOR 0xAARRGGBB)",
           color=2**32)
    raises(ValueError, "color holds values outside 0..=0xFFFFFFFF (D3DCOLORs 0xAARRGGBB)",
           color=np.array([0, -1, 0, 0]))
    raises(ValueError, "clear -0x1 is outside 0..=0xFFFFFFFF (a D3DCOLOR 0xAARRGGBB)", clear=-1)
    raises(ValueError, "x_range (1, 1) must be two finite numbers, low below high",
           x_range=(1, 1))
    raises(ValueError, "y_range (0, inf) must be two finite numbers, low below high",
           y_range=(0, float("inf")))
    raises(ValueError, "x_range must be None or two numbers (lo, hi)", x_range=(1, 2, 3))
    raises(ValueError, 'unknown blend "screen" (expected "add", "alpha", "max" or "replace")',
           blend="screen")
    raises(ValueError, 'unknown backend `metal` (expected "cpu" or "gpu")', backend="metal")
    raises(pointillist.Error, "render target 0x8 is outside 1..=16384 per side", width=0)
    raises(pointillist.Error, "render target 8x20000 is outside 1..=16384 per side",
           height=20000)


def test_sizes_and_names_of_any_value_are_one_clear_line():
    # Sizes no target has: the device's refusal, before the image is allocated (2**32 - 1
    # squared overflowed, a panic; 2**30 x 16 aborted the interpreter).
    for w, h in [(2**32 - 1, 2**32 - 1), (2**30, 16), (2**32, 8), (-1, 8), (8, -(2**70))]:
        raises(pointillist.Error, f"render target {w}x{h} is outside 1..=16384 per side",
               width=w, height=h)
    raises(TypeError, "width must be an integer; got 1.5", width=1.5)
    raises(TypeError, "height must be an integer; got True", height=True)
    raises(TypeError, "height must be an integer; got '8'", height="8")
    assert pointillist.points(X, X, width=np.int64(3), height=np.uint16(2)).shape == (2, 3, 4)
    raises(TypeError, 'blend must be a string ("add", "alpha", "max" or "replace"); got None',
           blend=None)
    raises(TypeError, 'backend must be a string ("cpu" or "gpu"); got 0', backend=0)
    # Two finite numbers whose span overflows: the real reason, the numbers in short.
    raises(ValueError, "x_range (-1e308, 1e308) is too wide: hi - lo overflows a float64",
           x_range=(-1e308, 1e308))
    raises(ValueError, "y_range (0, 5e-324) is too narrow", y_range=(0, 5e-324))


def test_save_errors_name_the_path_once(tmp_path):
    img = pointillist.points(X, X, width=4, height=4)
    missing = tmp_path / "none" / "a.png"
    with pytest.raises(pointillist.Error) as info:
        img.save(missing)
    assert str(info.value) == f"cannot write {missing}: folder {missing.parent} does not exist"
    assert not missing.parent.exists()
