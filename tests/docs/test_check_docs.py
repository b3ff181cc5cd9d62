"""The guide's link checker (tools/check_docs.py) on small books and pages made here:
it passes what resolves and fails, naming the link, on each kind of broken one.

    python3 -m unittest discover -s tests/docs      # or: python3 -m pytest tests/docs
"""
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "tools", "check_docs.py")


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def run(*args):
    done = subprocess.run([sys.executable, CHECKER, *args], capture_output=True, text=True)
    return done.returncode, done.stdout + done.stderr


class BuiltBook(unittest.TestCase):
    """A repository with docs/ (the book's source) and the HTML mdBook would write."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.repo = self.tmp.name
        self.src = os.path.join(self.repo, "docs")
        self.book = os.path.join(self.repo, "target", "book")
        write(os.path.join(self.repo, "examples", "run.sh"), "echo\n")
        write(os.path.join(self.src, "guide", "a.md"), "# A\n")
        write(os.path.join(self.book, "gallery", "x.png"), "png")
        write(os.path.join(self.book, "index.html"),
              '<a href="guide/a.html#usage">A</a> <a href="https://example.org/">out</a>')
        self.page(links='<img src="../gallery/x.png"> <a href="#usage">here</a>'
                        ' <a href="../../examples/run.sh">script</a>')

    def tearDown(self):
        self.tmp.cleanup()

    def page(self, links):
        write(os.path.join(self.book, "guide", "a.html"),
              '<h1 id="a">A</h1><h2 id="usage">Usage</h2><p>%s</p>' % links)

    def check(self):
        return run("html", self.book, self.src)

    def test_a_book_whose_links_resolve_passes(self):
        code, out = self.check()
        self.assertEqual(code, 0, out)
        self.assertIn("1 to repository files", out)

    def test_a_missing_page_fails(self):
        self.page(links='<a href="b.html">B</a>')
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("guide/a.html:1: b.html: no such file in the book", out)

    def test_a_missing_image_fails(self):
        self.page(links='<img src="../gallery/y.png">')
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("../gallery/y.png", out)

    def test_a_missing_heading_fails(self):
        write(os.path.join(self.book, "index.html"), '<a href="guide/a.html#nowhere">A</a>')
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("no id 'nowhere' on guide/a.html", out)

    def test_a_missing_repository_file_fails(self):
        self.page(links='<a href="../../examples/gone.sh">script</a>')
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("no such file in the repository (examples/gone.sh)", out)

    def test_a_link_out_of_the_repository_fails(self):
        self.page(links='<a href="../../../../etc/passwd">x</a>')
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("leaves the repository", out)


class Markdown(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        write(os.path.join(self.dir, "b.md"), "# The `render` command\n\n## Usage\n")

    def tearDown(self):
        self.tmp.cleanup()

    def check(self, text):
        write(os.path.join(self.dir, "a.md"), text)
        return run("markdown", self.dir)

    def test_links_that_resolve_pass(self):
        code, out = self.check(
            "[b](b.md) [usage](b.md#usage) [title](b.md#the-render-command) "
            "![img](b.md) <img src=\"b.md\"> [web](https://example.org/x.md)\n")
        self.assertEqual(code, 0, out)

    def test_a_missing_file_fails(self):
        code, out = self.check("see [c](c.md)\n")
        self.assertEqual(code, 1, out)
        self.assertIn("a.md:1: c.md: no such file", out)

    def test_a_missing_heading_fails(self):
        code, out = self.check("see [b](b.md#install)\n")
        self.assertEqual(code, 1, out)
        self.assertIn("no heading 'install'", out)

    def test_a_missing_image_in_html_fails(self):
        code, out = self.check('<img src="gallery/none.png" width="10">\n')
        self.assertEqual(code, 1, out)
        self.assertIn("gallery/none.png", out)

    def test_code_is_not_read_as_links(self):
        code, out = self.check("`[c](c.md)`\n\n```md\n[c](c.md)\n```\n")
        self.assertEqual(code, 0, out)


class Generated(unittest.TestCase):
    """The structure check of generated pages (`generated`): one title, no rustdoc link."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def check(self, text):
        write(os.path.join(self.dir, "c.md"), text)
        return run("generated", self.dir)

    def test_a_page_with_one_title_and_real_links_passes(self):
        code, out = self.check(
            "# C API\n\n## `f` (function)\n\n**Safety:** see [`T`](#t-type).\n\n"
            "```c\n# define X 1\nvoid f(void); // see T\n```\n")
        self.assertEqual(code, 0, out)

    def test_a_second_top_level_heading_fails(self):
        code, out = self.check("# C API\n\n## `f` (function)\n\n# Safety\nNULL.\n")
        self.assertEqual(code, 1, out)
        self.assertIn("c.md:5: # Safety: a second top-level heading", out)

    def test_a_rustdoc_link_fails_in_text_and_in_code(self):
        code, out = self.check(
            "# C API\n\nFill it with [`settings_default`].\n\n```c\n"
            "  // A [`GlyphcastColor::Uniform`].\n```\n")
        self.assertEqual(code, 1, out)
        self.assertIn("c.md:3: [`settings_default`]: a rustdoc-style link", out)
        self.assertIn("c.md:6: [`GlyphcastColor::Uniform`]: a rustdoc-style link", out)


if __name__ == "__main__":
    unittest.main()
