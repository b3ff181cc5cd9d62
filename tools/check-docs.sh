#!/usr/bin/env bash
# The user guide: builds the mdBook (docs/book.toml) into target/book and checks that
# every internal link and image resolves, in the built pages and in the Markdown of
# README.md and docs/, and that the generated reference pages (docs/reference/) hold one
# top-level heading each and no rustdoc-style link; that every marked performance figure
# is the one of docs/measurements.toml; that docs/guide/command-line.md names every
# option of each command's --help (docs/reference/cli/); and that docs/guide/settings.md's
# account of the C API is the header's. Exit 1 on a broken link, such a page, a figure,
# option or setting that disagrees, or a failed build.
#
#   bash tools/check-docs.sh               # build and check
#   bash tools/check-docs.sh --self-test   # also show that a broken page fails the check
#   bash tools/check-docs.sh --install     # only install the pinned mdBook if missing
#   bash tools/check-docs.sh --no-book [--self-test]   # only the checks of the Markdown
#
# mdBook: the `mdbook` on the PATH if it is the pinned version, else the one under
# target/tools/bin, installed there from crates.io on first use (a few minutes of
# compiling, once; CI can cache target/tools). MDBOOK=PATH names another binary.
set -euo pipefail
cd "$(dirname "$0")/.."

MDBOOK_VERSION=0.5.4
tools_root=target/tools

find_mdbook() {
    local candidate
    for candidate in "${MDBOOK:-}" "$tools_root/bin/mdbook" "$(command -v mdbook || true)"; do
        [ -n "$candidate" ] && [ -x "$candidate" ] || continue
        if [ -n "${MDBOOK:-}" ] || "$candidate" --version 2>/dev/null | grep -q "v$MDBOOK_VERSION\$"; then
            echo "$candidate"
            return 0
        fi
    done
    return 1
}

checks_of_the_sources() {
    echo "== links of README.md and docs/ as Markdown"
    python3 tools/check_docs.py markdown README.md docs
    echo "== the generated reference pages: one title each, no rustdoc-style link"
    python3 tools/check_docs.py generated docs/reference
    echo "== the performance figures of README.md and docs/ against docs/measurements.toml"
    python3 tools/check_docs.py figures docs/measurements.toml README.md docs
    echo "== docs/guide/command-line.md against each command's --help (docs/reference/cli)"
    python3 tools/check_docs.py cli docs/guide/command-line.md docs/reference/cli
    echo "== docs/guide/settings.md's C API against include/glyphcast.h"
    python3 tools/check_docs.py settings docs/guide/settings.md include/glyphcast.h
}

# A copy of a page with one thing changed must fail, naming the page and what changed.
expect_failure() {  # WHAT EXPECTED-LINE-PATTERN COMMAND...
    local what=$1 pattern=$2 report
    shift 2
    if report=$("$@" 2>&1); then
        echo "error: the check passed $what" >&2
        exit 1
    fi
    if ! grep -q -- "$pattern" <<<"$report"; then
        echo "error: the check of $what did not report it as expected ($pattern):" >&2
        echo "$report" >&2
        exit 1
    fi
    echo "ok: $what was reported:"
    grep -- "$pattern" <<<"$report"
}

self_test_of_the_sources() {
    local tmp
    tmp=$(mktemp -d)
    cp README.md "$tmp/README.md"
    cp docs/guide/command-line.md docs/guide/settings.md "$tmp/"
    echo "== self-test: a README with one figure changed must fail, naming the page and the measure"
    sed -i 's|<!-- fig:block-16/mesa22/culled-ms -->323 ms|<!-- fig:block-16/mesa22/culled-ms -->333 ms|' "$tmp/README.md"
    expect_failure "a README with one figure changed" \
        "^$tmp/README.md:[0-9]*: measure block-16/mesa22/culled-ms: the page says '333 ms'" \
        python3 tools/check_docs.py figures docs/measurements.toml "$tmp/README.md" docs
    echo "== self-test: a figure of a measure the registry lacks must fail, naming it"
    sed -i 's|fig:fodf-256-8/mesa25/frame-ms|fig:fodf-256-8/mesa24/frame-ms|' "$tmp/README.md"
    expect_failure "a figure of an unknown measure" \
        "measure fodf-256-8/mesa24/frame-ms: no such measure" \
        python3 tools/check_docs.py figures docs/measurements.toml "$tmp/README.md" docs
    echo "== self-test: command-line.md without one option of render must fail, naming it"
    sed -i 's/\[--underlay-plane back|centre\]//' "$tmp/command-line.md"
    expect_failure "command-line.md without render's --underlay-plane" \
        "glyphcast render: --underlay-plane (in its --help" \
        python3 tools/check_docs.py cli "$tmp/command-line.md" docs/reference/cli
    echo "== self-test: settings.md saying the C API lacks path must fail, naming it"
    sed -i 's/ and `cull` (an engine/, `path` and `cull` (an engine/' "$tmp/settings.md"
    expect_failure "settings.md claiming the C API lacks path" \
        "says the C API lacks \`path\`, but include/glyphcast.h" \
        python3 tools/check_docs.py settings "$tmp/settings.md" include/glyphcast.h
    rm -rf "$tmp"
}

if [ "${1:-}" = "--no-book" ]; then
    echo "== the link checker's own tests (tests/docs)"
    python3 -m unittest discover -q -s tests/docs
    checks_of_the_sources
    if [ "${2:-}" = "--self-test" ]; then
        self_test_of_the_sources
    fi
    exit 0
fi

if ! mdbook=$(find_mdbook); then
    echo "== installing mdbook $MDBOOK_VERSION into $tools_root (once)" >&2
    # Only the HTML renderer with its search index: no local server, no file watcher.
    nice -n 19 cargo install mdbook --version "$MDBOOK_VERSION" --locked \
        --no-default-features --features search --root "$tools_root" --quiet
    mdbook=$tools_root/bin/mdbook
fi
if [ "${1:-}" = "--install" ]; then
    echo "mdbook: $("$mdbook" --version)"
    exit 0
fi

echo "== mdbook build docs ($("$mdbook" --version))"
rm -rf target/book
"$mdbook" build docs 2>&1 | { grep -v '^ INFO ' || true; }
test -f target/book/index.html || { echo "error: mdbook wrote no target/book/index.html" >&2; exit 1; }

echo "== the link checker's own tests (tests/docs)"
python3 -m unittest discover -q -s tests/docs
echo "== links of the built book"
python3 tools/check_docs.py html target/book docs
checks_of_the_sources

if [ "${1:-}" = "--self-test" ]; then
    self_test_of_the_sources
    echo "== self-test: a copy of the guide with one broken link must fail, naming it"
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    cp -r docs "$tmp/docs"
    # The guide's links to repository files (examples/...) resolve in the copy too.
    for d in examples tools tests include python; do ln -s "$PWD/$d" "$tmp/$d"; done
    sed -i 's/^build-dir = .*/build-dir = "..\/book"/' "$tmp/docs/book.toml"
    printf '\nSee [a page that is not there](no-such-page.md).\n' >> "$tmp/docs/introduction.md"
    "$mdbook" build "$tmp/docs" >/dev/null 2>&1
    if report=$(python3 tools/check_docs.py html "$tmp/book" "$tmp/docs" 2>&1); then
        echo "error: the checker passed a book with a broken link" >&2
        exit 1
    fi
    if ! grep -q '^introduction.html:[0-9]*: no-such-page.html: no such file' <<<"$report" \
        || [ "$(grep -c ': no such file' <<<"$report")" != 2 ]; then
        echo "error: the checker did not report exactly the broken link (on the page and its index copy):" >&2
        echo "$report" >&2
        exit 1
    fi
    echo "ok: the broken link was reported:"
    grep '^introduction.html' <<<"$report"
fi
