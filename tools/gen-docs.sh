#!/usr/bin/env bash
# Writes what the docs generate from the code: the command-line reference (a Markdown page
# per command, man pages, bash/zsh/fish completions) and the Python and C API references
# (tools/gen_api_reference.py) into docs/reference/, the render settings table of
# docs/guide/settings.md and the render settings' keywords of docs/guide/python.md. Tests
# fail when the committed files differ from what this makes (crates/glyphcast-cli's
# `the_committed_reference_is_current`, the core's `the_docs_settings_table_is_current`
# and `the_python_guide_keywords_are_current`).
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/env.sh
rm -rf docs/reference
cargo run --locked --quiet -p glyphcast-cli -- reference docs/reference
# The Python and C API references, from the docstrings and the header's comments.
python3 tools/gen_api_reference.py docs/reference
GLYPHCAST_BLESS=1 cargo test --locked --quiet -p glyphcast --lib -- \
    render::table::tests::the_docs_settings_table_is_current \
    render::table::tests::the_python_guide_keywords_are_current >/dev/null
echo "wrote docs/reference/, the table of docs/guide/settings.md and the render keywords" \
    "of docs/guide/python.md"
