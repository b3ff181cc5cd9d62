"""Shadows through the Python module: `shadows=True` draws what `glyphcast render
--shadows` draws (depth and PNG, bit for bit), `shadows="soft:R"` what `--shadows soft:R`
draws; `ambient_occlusion=True` or a reach what `--ambient-occlusion [REACH]` draws;
shadows and occlusion keep the depth map and only darken; bad values raise ValueError
naming the keyword."""
import numpy as np
import pytest

import glyphcast
from conftest import assert_same_depth

SIZE = dict(width=160, height=120, light=(-1.0, 0.3, 0.4))
CLI_SIZE = ("--width", 160, "--height", 120, "--light", "-1,0.3,0.4")


@pytest.mark.parametrize("key, value, flags", [
    ("shadows", True, ("--shadows",)),
    ("shadows", "soft:6", ("--shadows", "soft:6")),
    ("ambient_occlusion", True, ("--ambient-occlusion",)),
    ("ambient_occlusion", 2, ("--ambient-occlusion", "2")),
    ("ambient_occlusion", "0.5", ("--ambient-occlusion", "0.5")),
])
def test_rays_from_the_hits_match_the_cli(scenes, cli_render, key, value, flags):
    scene = scenes / "order4_pair.json"
    depth, png = cli_render(scene, *CLI_SIZE, *flags)
    ours = glyphcast.render_scene(scene, **{key: value}, **SIZE)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    plain = glyphcast.render_scene(scene, **{key: False}, **SIZE)
    assert np.array_equal(plain.depth, ours.depth, equal_nan=True)
    darker = (ours.rgba[..., :3] < plain.rgba[..., :3]).any(axis=-1).sum()
    assert darker > 60
    assert not (ours.rgba > plain.rgba).any()


def test_bad_shadow_values_name_the_keyword(scenes):
    scene = scenes / "order4_pair.json"
    for value, words in [("soft:0", "above 0"), ("sometimes", "soft:RADIUS"),
                         (3, "not a name"), ([1], "True, False, a number or a string")]:
        with pytest.raises((ValueError, TypeError)) as caught:
            glyphcast.render_scene(scene, shadows=value, **SIZE)
        message = str(caught.value)
        assert message.startswith("shadows"), message
        assert words in message, message
    with pytest.raises(ValueError) as caught:
        glyphcast.render_scene(scene, shadows=True, method="fixed", **SIZE)
    assert "method=exact" in str(caught.value)


def test_bad_ambient_occlusion_values_name_the_keyword(scenes):
    scene = scenes / "order4_pair.json"
    for value, words in [(0, "above 0"), (40.0, "at most 16"), ("often", "reach"),
                         ([1, 2], "True, False, a number or a string")]:
        with pytest.raises((ValueError, TypeError)) as caught:
            glyphcast.render_scene(scene, ambient_occlusion=value, **SIZE)
        message = str(caught.value)
        assert message.startswith("ambient_occlusion"), message
        assert words in message, message
    with pytest.raises(ValueError) as caught:
        glyphcast.render_scene(scene, ambient_occlusion=True, method="affine", **SIZE)
    assert "method=exact" in str(caught.value)


@pytest.mark.parametrize("key, value", [("shadows", True), ("ambient_occlusion", 1)])
def test_shapes_that_take_no_rays_are_named_in_a_warning(key, value):
    """Young's modulus is a reciprocal glyph, which takes no shadow or occlusion rays:
    asked for them, it is drawn as without them, with a warning that names the shape
    (the CLI's note); without them, nothing is said."""
    import warnings
    copper = np.array([
        [168.4, 121.4, 121.4, 0, 0, 0],
        [121.4, 168.4, 121.4, 0, 0, 0],
        [121.4, 121.4, 168.4, 0, 0, 0],
        [0, 0, 0, 75.4, 0, 0],
        [0, 0, 0, 0, 75.4, 0],
        [0, 0, 0, 0, 0, 75.4],
    ])
    size = dict(width=64, height=48)
    with pytest.warns(UserWarning, match="shape reciprocal .*no shadows"):
        asked, _ = glyphcast.stiffness(copper, surface="young", **{key: value}, **size)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plain, _ = glyphcast.stiffness(copper, surface="young", **size)
    assert np.isfinite(plain.depth).sum() > 300
    assert np.array_equal(asked.rgba, plain.rgba)
