"""docs/reference/python.md and c.md are what tools/gen_api_reference.py makes of the
module's docstrings and the C header now; and they hold every exported name."""
import pathlib
import sys
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


if __name__ == "__main__":
    unittest.main()
