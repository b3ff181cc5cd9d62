"""The API reference pages of the guide, made from the code's own documentation:
docs/reference/python.md from the docstrings of the Python module (python/glyphcast, read
with ast, not imported: no build needed) and the doc comments of its native functions
(python/src/lib.rs), and docs/reference/c.md from the comments of include/glyphcast.h
(cbindgen's copy of capi/src/lib.rs's docs). tools/gen-docs.sh runs it; the docs' tests
(tests/docs) fail when the committed pages differ from what it makes.

    python3 tools/gen_api_reference.py OUTDIR     (default: docs/reference)
"""
import ast
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def _rust_docs(source: str) -> dict:
    """The `///` doc comment of each `fn NAME` in Rust `source`."""
    docs, pending = {}, []
    for line in source.splitlines():
        stripped = line.strip()
        if stripped.startswith("///"):
            pending.append(stripped[3:].strip())
        elif stripped.startswith("#["):
            continue
        else:
            match = re.match(r"(?:pub )?fn (\w+)", stripped)
            if match and pending:
                docs[match.group(1)] = " ".join(pending)
            pending = []
    return docs


def _signature(node: ast.FunctionDef) -> str:
    args = ast.unparse(node.args)
    returns = f" -> {ast.unparse(node.returns)}" if node.returns else ""
    return f"{node.name}({args}){returns}"


def python_reference() -> str:
    source = (ROOT / "python" / "glyphcast" / "__init__.py").read_text()
    tree = ast.parse(source)
    exported = []
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            exported = ast.literal_eval(node.value)
    defined = {
        node.name: node
        for node in tree.body
        if isinstance(node, (ast.FunctionDef, ast.ClassDef))
    }
    native = _rust_docs((ROOT / "python" / "src" / "lib.rs").read_text())
    out = [
        "# Python API reference",
        "",
        "Generated from the module's docstrings by `bash tools/gen-docs.sh`.",
        "",
        ast.get_docstring(tree) or "",
        "",
    ]
    for name in exported:
        node = defined.get(name)
        if isinstance(node, ast.ClassDef):
            out += [f"## class `{name}`", "", ast.get_docstring(node) or "", ""]
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and not item.name.startswith("_"):
                    doc = ast.get_docstring(item) or ""
                    out += [f"### `{name}.{_signature(item)}`", "", doc, ""]
        elif isinstance(node, ast.FunctionDef):
            out += [f"## `{_signature(node)}`", "", ast.get_docstring(node) or "", ""]
        elif name in native:
            out += [f"## `{name}`", "", native[name], ""]
    out += _notebook_reference()
    return "\n".join(out).rstrip() + "\n"


def _notebook_reference() -> list:
    """The notebook view's section: python/glyphcast/notebook.py's docstring and its
    exported names (a property's setter is its getter's entry)."""
    tree = ast.parse((ROOT / "python" / "glyphcast" / "notebook.py").read_text())
    exported = next(
        ast.literal_eval(node.value) for node in tree.body
        if isinstance(node, ast.Assign)
        and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets)
    )
    defined = {
        node.name: node
        for node in tree.body
        if isinstance(node, (ast.FunctionDef, ast.ClassDef))
    }
    out = ["## The notebook view (`glyphcast.notebook`)", "", ast.get_docstring(tree) or "", ""]
    for name in exported:
        node = defined[name]
        if isinstance(node, ast.ClassDef):
            out += [f"### class `{name}`", "", ast.get_docstring(node) or "", ""]
            seen = set()
            for item in node.body:
                if (isinstance(item, ast.FunctionDef) and not item.name.startswith("_")
                        and item.name not in seen):
                    seen.add(item.name)
                    doc = ast.get_docstring(item) or ""
                    out += [f"#### `{name}.{_signature(item)}`", "", doc, ""]
        else:
            out += [f"### `{_signature(node)}`", "", ast.get_docstring(node) or "", ""]
    return out


# A rustdoc intra-doc link, [`Name`] or [`Name::member`], not followed by a target.
RUSTDOC_LINK = re.compile(r"\[`(\w+)(?:::(\w+))?`\](?!\()")
# A Markdown heading in a doc comment (`# Safety`): a paragraph's lead-in on the page.
DOC_HEADING = re.compile(r"^#{1,6} +(.+?)\s*$")


def _anchor(heading: str) -> str:
    """The id mdBook gives a heading (tools/check_docs.py's heading_id)."""
    text = heading.replace("`", "").strip().lower()
    return "".join(c for c in text if c.isalnum() or c in " -_").replace(" ", "-")


def _c_names(header: list) -> tuple:
    """The page's sections (name to anchor) and each enum's constants (enum name to
    its constants) of the header."""
    sections, constants, current = {}, {}, None
    for line in header:
        match = re.match(r"(?:typedef )?(struct|enum) (\w+)(?: \{|$)", line)
        function = re.match(r"\w[\w *]*?[ *](glyphcast_\w+)\(", line)
        if match:
            sections[match.group(2)] = _anchor(f"`{match.group(2)}` (type)")
            current = match.group(2) if match.group(1) == "enum" else None
            constants.setdefault(match.group(2), [])
        elif function:
            sections[function.group(1)] = _anchor(f"`{function.group(1)}` (function)")
        elif line.startswith("}"):
            current = None
        elif current:
            constant = re.match(r"\s+(GLYPHCAST_\w+)\s*=", line)
            if constant:
                constants[current].append(constant.group(1))
    return sections, constants


def _c_spelling(name: str, member, constants: dict) -> str:
    """How C spells a rustdoc path: an enum's variant as its constant
    (`GlyphcastColor::Uniform` is `GLYPHCAST_COLOR_UNIFORM`), a struct's field as
    `Struct.field`, anything else as its name."""
    if not member:
        return name
    snake = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", member).upper()
    for constant in constants.get(name, []):
        if constant.endswith("_" + snake):
            return constant
    return f"{name}.{member}"


def _c_links(text: str, sections: dict, constants: dict, in_code: bool) -> str:
    """The rustdoc links of a doc comment made Markdown: a link to the section of the
    type or function it names on this page (a code span where no section names it), or
    in a code block's comment the C spelling alone."""
    def replace(match):
        name, member = match.group(1), match.group(2)
        spelled = _c_spelling(name, member, constants)
        if in_code:
            return spelled
        if name in sections:
            return f"[`{spelled}`](#{sections[name]})"
        return f"`{spelled}`"
    return RUSTDOC_LINK.sub(replace, text)


def _c_comment(lines: list, sections: dict, constants: dict) -> str:
    """A doc comment as the page's text: rustdoc links resolved, a heading (`# Safety`)
    made the bold lead-in of its paragraph, not a chapter of the book."""
    out = []
    for line in lines:
        heading = DOC_HEADING.match(line)
        if heading:
            if out and out[-1]:
                out.append("")
            out.append(f"**{heading.group(1)}:**")
        else:
            out.append(_c_links(line, sections, constants, in_code=False))
    return "\n".join(out).strip()


def c_reference() -> str:
    header = (ROOT / "include" / "glyphcast.h").read_text().splitlines()
    sections, constants = _c_names(header)
    out = [
        "# C API reference",
        "",
        "Generated from `include/glyphcast.h` by `bash tools/gen-docs.sh`; the header is",
        "generated from the C API's Rust source by cbindgen. Types first, then functions.",
        "",
    ]
    comment: list = []
    i = 0
    while i < len(header):
        line = header[i]
        stripped = line.strip()
        if stripped.startswith("//") and not line.startswith("  "):
            comment.append(stripped[2:].strip())
            i += 1
            continue
        match = re.match(
            r"(?:typedef )?(struct|enum) (\w+)(?: \{|$)|\w[\w *]*?[ *](glyphcast_\w+)\(",
            line,
        )
        if match and comment:
            name = match.group(2) or match.group(3)
            block = [line]
            if match.group(1):
                # A type: to its closing brace (an opaque struct is one line).
                if not line.rstrip().endswith(";"):
                    while not header[i].startswith("}"):
                        i += 1
                        block.append(header[i])
            else:
                while not header[i].rstrip().endswith(";"):
                    i += 1
                    block.append(header[i])
            kind = "type" if match.group(1) else "function"
            code = _c_links("\n".join(block), sections, constants, in_code=True)
            out += [f"## `{name}` ({kind})", "", _c_comment(comment, sections, constants),
                    "", "```c", code, "```", ""]
        comment = []
        i += 1
    return "\n".join(out).rstrip() + "\n"


def pages() -> dict:
    return {"python.md": python_reference(), "c.md": c_reference()}


if __name__ == "__main__":
    target = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "reference"
    target.mkdir(parents=True, exist_ok=True)
    for name, text in pages().items():
        (target / name).write_text(text)
