#!/usr/bin/env bash
# The user guide: builds the mdBook (docs/book.toml) into target/book and checks that
# every internal link and image resolves, in the built pages and in the Markdown of
# README.md and docs/, and that the generated reference pages (docs/reference/) hold one
# top-level heading each and no rustdoc-style link. Exit 1 on a broken link, such a
# page or a failed build.
#
#   bash tools/check-docs.sh               # build and check
#   bash tools/check-docs.sh --self-test   # also show that a broken page fails the check
#   bash tools/check-docs.sh --install     # only install the pinned mdBook if missing
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
echo "== links of README.md and docs/ as Markdown"
python3 tools/check_docs.py markdown README.md docs
echo "== the generated reference pages: one title each, no rustdoc-style link"
python3 tools/check_docs.py generated docs/reference

if [ "${1:-}" = "--self-test" ]; then
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
