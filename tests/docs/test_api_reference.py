"""docs/reference/python.md and c.md are what tools/gen_api_reference.py makes of the
module's docstrings and the C header now; and they hold every exported name."""
import pathlib
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))

import gen_api_reference  # noqa: E402


class ApiReference(unittest.TestCase):
    def test_the_committed_pages_are_current(self):
        for name, text in gen_api_reference.pages().items():
            committed = (ROOT / "docs" / "reference" / name).read_text()
            self.assertEqual(committed, text,
                             f"docs/reference/{name} is stale: run bash tools/gen-docs.sh")

    def test_every_exported_name_has_a_section(self):
        pages = gen_api_reference.pages()
        for name in ["Rendering", "Renderer", "render_scene", "render_sh", "render_tensor",
                     "stiffness", "encode_png", "render_settings"]:
            self.assertIn(f"`{name}", pages["python.md"], name)
        header = (ROOT / "include" / "glyphcast.h").read_text()
        functions = {line.split("(")[0].split()[-1].lstrip("*")
                     for line in header.splitlines() if "glyphcast_" in line and "(" in line
                     and not line.startswith((" ", "/", "#"))}
        self.assertGreater(len(functions), 5)
        for function in functions:
            self.assertIn(f"## `{function}` (function)", pages["c.md"], function)

    def test_the_pages_pass_the_structure_check(self):
        # What tools/check-docs.sh's `generated` check reads: one title a page, no
        # rustdoc-style link left from the doc comments.
        import check_docs
        with tempfile.TemporaryDirectory() as tmp:
            for name, text in gen_api_reference.pages().items():
                (pathlib.Path(tmp) / name).write_text(text)
            found, counts = check_docs.check_structure([tmp])
        self.assertEqual(counts["files"], 2)
        self.assertEqual(found, [])

    def test_rustdoc_links_become_links_to_the_page_or_c_names(self):
        c = gen_api_reference.pages()["c.md"]
        self.assertIn("[`GlyphcastSettings.method`](#glyphcastsettings-type)", c)
        self.assertIn("  // With GLYPHCAST_COLOR_UNIFORM: linear RGB", c)
        self.assertIn("**Safety:**", c)


if __name__ == "__main__":
    unittest.main()
