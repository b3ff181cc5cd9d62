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


@pytest.mark.parametrize("keyword, flag", [(True, ()), ("soft:6", ("soft:6",))])
def test_shadows_match_the_cli(scenes, cli_render, keyword, flag):
    scene = scenes / "order4_pair.json"
    depth, png = cli_render(scene, *CLI_SIZE, "--shadows", *flag)
    ours = glyphcast.render_scene(scene, shadows=keyword, **SIZE)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    plain = glyphcast.render_scene(scene, shadows=False, **SIZE)
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


@pytest.mark.parametrize("keyword, flag", [(True, ()), (2, ("2",)), ("0.5", ("0.5",))])
def test_ambient_occlusion_matches_the_cli(scenes, cli_render, keyword, flag):
    scene = scenes / "order4_pair.json"
    depth, png = cli_render(scene, *CLI_SIZE, "--ambient-occlusion", *flag)
    ours = glyphcast.render_scene(scene, ambient_occlusion=keyword, **SIZE)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    plain = glyphcast.render_scene(scene, ambient_occlusion=False, **SIZE)
    assert np.array_equal(plain.depth, ours.depth, equal_nan=True)
    darker = (ours.rgba[..., :3] < plain.rgba[..., :3]).any(axis=-1).sum()
    assert darker > 60
    assert not (ours.rgba > plain.rgba).any()


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
