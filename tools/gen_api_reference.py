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
    return "\n".join(out).rstrip() + "\n"


def c_reference() -> str:
    header = (ROOT / "include" / "glyphcast.h").read_text().splitlines()
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
            out += [f"## `{name}` ({kind})", "", "\n".join(comment).strip(), "",
                    "```c", "\n".join(block), "```", ""]
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
