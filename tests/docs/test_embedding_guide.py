"""The embedding guide lists every option of the C example engine (examples/c/main.c):
the options its argument loop compares with, each in the guide's usage line and
explained after it."""
import pathlib
import re
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]


class EmbeddingGuide(unittest.TestCase):
    def test_every_option_of_the_c_example_is_in_the_guide(self):
        source = (ROOT / "examples" / "c" / "main.c").read_text()
        options = set(re.findall(r'strcmp\(argv\[i\], "(--[a-z-]+)"\)', source))
        self.assertGreater(len(options), 5, options)
        guide = (ROOT / "docs" / "guide" / "embedding.md").read_text()
        usage = re.search(r"`bash tools/c-example\.sh OUT\.png ([^`]*)`", guide)
        self.assertIsNotNone(usage, "the guide's usage line of tools/c-example.sh")
        usage = " ".join(usage.group(1).split())
        missing = sorted(o for o in options if f"[{o}" not in usage)
        self.assertEqual(missing, [], f"not in the guide's usage line: {usage}")
        unexplained = sorted(o for o in options if f"`{o}`:" not in guide
                             and f"`{o}`, with" not in guide)
        self.assertEqual(unexplained, [], "options the guide does not explain")


if __name__ == "__main__":
    unittest.main()
