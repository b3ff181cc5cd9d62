#!/usr/bin/env python3
"""Link check of the user guide (standard library only).

    python3 tools/check_docs.py html BOOK_DIR SRC_DIR    # the built book (mdbook build)
    python3 tools/check_docs.py markdown FILE_OR_DIR...  # Markdown sources as they are

`html` reads every page mdBook wrote into BOOK_DIR and checks each internal `href` and
`src` (links, images, style sheets, scripts): the file must exist in the book, and a
`#fragment` must name an `id` (or `name`) on the target page. A link that leaves the
book (`../../examples/slurm/qc-array.sbatch` from a guide page) is resolved the way a
reader browsing the repository follows it: from the page's source file in SRC_DIR, and
the file must exist in the repository.

`markdown` checks the relative links and images of Markdown files (README.md, the
guide's pages) against the files beside them, with the same rule for fragments that
point into another Markdown file: the heading must exist (GitHub's and mdBook's
heading ids). Code blocks and code spans are skipped.

`generated` checks the pages the docs generate from the code (docs/reference/): one
top-level heading each, the title (a `# Safety` of a doc comment would be a chapter of
the book), and no rustdoc-style link (`[`Name`]` with no target, shown as brackets).

    python3 tools/check_docs.py generated FILE_OR_DIR...

`figures` checks the performance figures of the pages against the registry of
measurements (docs/measurements.toml): a figure is marked in the Markdown, invisible in
the rendered page, as `<!-- fig:NAME -->323 ms<!-- /fig -->`, on one line. The numbers
of the marked text must be the registry's `values` of measure NAME, in order; a NAME
the registry does not hold, two pages stating different numbers for one measure, and a
measure of the registry that no page marks are errors too.

    python3 tools/check_docs.py figures REGISTRY FILE_OR_DIR...

`cli` checks docs/guide/command-line.md against the generated command-line reference
(docs/reference/cli/COMMAND.md, which a Rust test keeps equal to each `--help`): the
section of each command (a level-2 heading naming `glyphcast COMMAND`) must name every
long option of the command (or its short form, `-o`). A section may take the options
of another command's section with `<!-- options of: render -->`, and leave options to
the reference page by name with `<!-- options left to the reference: --foo --bar -->`.
An option the section's synopsis (its code blocks' `glyphcast COMMAND` lines) names
that the command does not have is an error too.

    python3 tools/check_docs.py cli GUIDE_PAGE REFERENCE_DIR

`settings` checks docs/guide/settings.md's account of the C API against the C header:
the settings named (in code spans) between `<!-- c-api: lacks -->` and `<!-- /c-api -->`
must be exactly the settings of the page's table that are no field of the header's
`GlyphcastSettings` (a setting's field is its name with spaces as underscores).

    python3 tools/check_docs.py settings SETTINGS_PAGE HEADER

Exit status 1 with one line per broken link (`FILE: TARGET: why`), 0 when every link
resolves.
"""
import os
import re
import sys
import urllib.parse
from html.parser import HTMLParser

EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto:, data:...


class Page(HTMLParser):
    """The links and the ids of one HTML page."""

    LINK_ATTRS = {"a": "href", "link": "href", "img": "src", "script": "src",
                  "iframe": "src", "source": "src"}

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.links = []  # (line, url)
        self.ids = set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("id", "name"):
            if attrs.get(key):
                self.ids.add(attrs[key])
        want = self.LINK_ATTRS.get(tag)
        if want and attrs.get(want):
            self.links.append((self.getpos()[0], attrs[want]))

    handle_startendtag = handle_starttag


def read_page(path, cache):
    if path not in cache:
        page = Page()
        with open(path, encoding="utf-8", errors="replace") as f:
            page.feed(f.read())
        page.close()
        cache[path] = page
    return cache[path]


def check_html(book, src):
    """Broken links of the built book, as (file, line, url, why)."""
    book = os.path.realpath(book)
    src = os.path.realpath(src)
    repo = os.path.dirname(src)
    cache, broken, counts = {}, [], {"pages": 0, "links": 0, "repository": 0}
    for root, _, files in os.walk(book):
        for name in sorted(files):
            if not name.endswith(".html"):
                continue
            path = os.path.join(root, name)
            # print.html is every chapter on one page, with links rewritten by mdBook's
            # script; 404.html is served from the site root. Both repeat the chapters'
            # links, so the chapters' own pages are what is checked.
            if os.path.relpath(path, book) in ("print.html", "404.html", "toc.html"):
                continue
            counts["pages"] += 1
            page = read_page(path, cache)
            for line, url in page.links:
                counts["links"] += 1
                why = check_html_link(book, repo, src, path, url, cache, counts)
                entry = (os.path.relpath(path, book), line, url, why)
                # mdBook writes each Markdown image twice (the image and its zoomed
                # copy): one report per link and line.
                if why and entry not in broken:
                    broken.append(entry)
    return broken, counts


def check_html_link(book, repo, src, page_path, url, cache, counts):
    if EXTERNAL.match(url) or url.startswith("//"):
        return None
    parts = urllib.parse.urlsplit(url)
    target = urllib.parse.unquote(parts.path)
    fragment = urllib.parse.unquote(parts.fragment)
    if target.startswith("/"):
        return "an absolute path (the book may be served from any folder)"
    if target == "":
        dest = page_path
    else:
        dest = os.path.normpath(os.path.join(os.path.dirname(page_path), target))
    if dest != book and not dest.startswith(book + os.sep):
        # Outside the book: a file of the repository, named from the page's source.
        counts["repository"] += 1
        page_rel = os.path.relpath(page_path, book)
        source_dir = os.path.dirname(os.path.join(src, page_rel))
        in_repo = os.path.normpath(os.path.join(source_dir, target))
        if not (in_repo == repo or in_repo.startswith(repo + os.sep)):
            return "leaves the repository"
        if not os.path.exists(in_repo):
            return "no such file in the repository (%s)" % os.path.relpath(in_repo, repo)
        return None
    if os.path.isdir(dest):
        dest = os.path.join(dest, "index.html")
    if not os.path.exists(dest):
        return "no such file in the book (%s)" % os.path.relpath(dest, book)
    if fragment and dest.endswith(".html"):
        if fragment not in read_page(dest, cache).ids:
            return "no id '%s' on %s" % (fragment, os.path.relpath(dest, book))
    return None


# Markdown ---------------------------------------------------------------------------

FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")
MD_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_LINK = re.compile(r"<(?:img|a|source)\b[^>]*?\b(?:src|href)\s*=\s*\"([^\"]+)\"", re.I)
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def heading_id(text):
    """The id GitHub and mdBook give a heading: lower case, markup and punctuation
    dropped, spaces to hyphens."""
    text = re.sub(r"<[^>]+>", "", text)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.replace("`", "").strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def markdown_lines(path, keep_code_spans=False):
    """(line number, text) of a Markdown file outside code blocks, code spans removed
    unless `keep_code_spans` (headings keep theirs: their text makes the id)."""
    inside = None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fence = FENCE.match(line)
            if fence:
                if inside is None:
                    inside = fence.group(1)
                elif fence.group(1) == inside:
                    inside = None
                continue
            if inside is None:
                yield number, line if keep_code_spans else CODE_SPAN.sub("", line)


def markdown_ids(path, cache):
    if path not in cache:
        ids, seen = set(), {}
        for _, line in markdown_lines(path, keep_code_spans=True):
            m = HEADING.match(line)
            if m:
                base = heading_id(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                ids.add(base if n == 0 else "%s-%d" % (base, n))
            for anchor in re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", line):
                ids.add(anchor)
        cache[path] = ids
    return cache[path]


def markdown_files(paths):
    """The Markdown files of `paths`: files as given, folders walked in sorted order
    (hidden ones left out)."""
    files = []
    for p in paths:
        if os.path.isdir(p):
            for root, dirs, names in os.walk(p):
                dirs[:] = sorted(d for d in dirs if not d.startswith("."))
                files += [os.path.join(root, n) for n in sorted(names) if n.endswith(".md")]
        else:
            files.append(p)
    return files


def check_markdown(paths):
    files = markdown_files(paths)
    cache, broken, links = {}, [], 0
    for path in files:
        for number, line in markdown_lines(path):
            for url in MD_LINK.findall(line) + HTML_LINK.findall(line):
                links += 1
                why = check_markdown_link(path, url, cache)
                if why:
                    broken.append((path, number, url, why))
    return broken, {"files": len(files), "links": links}


def check_markdown_link(path, url, cache):
    if EXTERNAL.match(url) or url.startswith("//"):
        return None
    parts = urllib.parse.urlsplit(url)
    target = urllib.parse.unquote(parts.path)
    fragment = urllib.parse.unquote(parts.fragment)
    if target.startswith("/"):
        return "an absolute path"
    dest = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
    if not os.path.exists(dest):
        return "no such file (%s)" % dest
    if fragment and dest.endswith(".md") and fragment not in markdown_ids(dest, cache):
        return "no heading '%s' in %s" % (fragment, dest)
    return None


# Pages as generated ------------------------------------------------------------------

# A rustdoc intra-doc link ([`Name`], [`Name::member`]) copied from a doc comment: no
# target, so the page shows the brackets, and a reader has nowhere to go.
RUSTDOC_LINK = re.compile(r"\[`[\w:]+`\](?![(\[])")


def check_structure(paths):
    """What a generated page (docs/reference/) must not hold, as (file, line, text,
    why): a level-1 heading after its title (the book shows it as a chapter of its
    own, `# Safety` from a doc comment), and a rustdoc-style link, in the text or in a
    code block."""
    files = markdown_files(paths)
    found = []
    for path in files:
        titles = 0
        for number, line in markdown_lines(path, keep_code_spans=True):
            m = HEADING.match(line)
            if m and len(m.group(1)) == 1:
                titles += 1
                if titles > 1:
                    found.append((path, number, line.strip(), "a second top-level heading"))
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for link in RUSTDOC_LINK.findall(line):
                    found.append((path, number, link, "a rustdoc-style link, to nowhere"))
    return found, {"files": len(files)}


# Figures against the registry of measurements ----------------------------------------

FIGURE = re.compile(r"<!--\s*fig:([^\s>]+)\s*-->(.*?)<!--\s*/fig\s*-->")
FIGURE_OPEN = re.compile(r"<!--\s*fig:")
NUMBER = re.compile(r"\d[\d,]*(?:\.\d+)?(?:e-?\d+)?")
REQUIRED = ("values", "unit", "date", "machine", "driver", "command")


def numbers(text):
    """The numbers of a figure's text, as floats (`1,406,000` is one number; a `10^6`
    gives 10 and 6)."""
    return [float(n.replace(",", "")) for n in NUMBER.findall(text)]


def load_registry(path):
    """The measures of the registry (TOML: one `[measure."NAME"]` table each), and the
    problems of its entries."""
    import tomllib
    with open(path, "rb") as f:
        measures = tomllib.load(f).get("measure", {})
    problems = []
    for name, m in measures.items():
        for key in REQUIRED:
            if key not in m:
                problems.append("%s: measure %s has no '%s'" % (path, name, key))
        if not re.fullmatch(r"\d{4}-\d{2}-\d{2}", str(m.get("date", ""))):
            problems.append("%s: measure %s: date %r is not YYYY-MM-DD" % (path, name, m.get("date")))
        if not all(isinstance(v, (int, float)) for v in m.get("values", [None])):
            problems.append("%s: measure %s: values must be numbers" % (path, name))
    return measures, problems


def check_figures(registry, paths):
    """Problems of the marked figures, as lines `FILE:LINE: measure NAME: why`."""
    measures, problems = load_registry(registry)
    found, stated = [], {}
    for path in markdown_files(paths):
        for number, line in markdown_lines(path, keep_code_spans=True):
            figures = FIGURE.findall(line)
            if len(FIGURE_OPEN.findall(line)) != len(figures):
                problems.append("%s:%d: a figure marker that does not close on its line" % (path, number))
            found += [(path, number, name, text) for name, text in figures]
    for path, number, name, text in found:
        where = "%s:%d: measure %s" % (path, number, name)
        stated.setdefault(name, {}).setdefault(tuple(numbers(text)), []).append("%s:%d" % (path, number))
        if name not in measures:
            problems.append("%s: no such measure in %s" % (where, registry))
            continue
        want = [float(v) for v in measures[name].get("values", [])]
        if numbers(text) != want:
            problems.append("%s: the page says %r, the registry %s %s (%s)" % (
                where, text.strip(), " / ".join("%g" % v for v in want),
                measures[name].get("unit", ""), measures[name].get("date", "")))
    for name, values in sorted(stated.items()):
        if len(values) > 1:
            problems.append("measure %s: pages state different values: %s" % (name, "; ".join(
                "%s at %s" % (" / ".join("%g" % v for v in vals), ", ".join(places))
                for vals, places in values.items())))
    for name in sorted(set(measures) - set(stated)):
        problems.append("%s: measure %s: no page states it" % (registry, name))
    return problems, {"figures": len(found), "measures": len(measures)}


# command-line.md against the reference pages ------------------------------------------

REF_OPTION = re.compile(r"^- `(?:(-\w), )?(--[\w-]+)")
SECTION = re.compile(r"^##\s+.*?`glyphcast (\w+)")
OPTIONS_OF = re.compile(r"<!--\s*options of:\s*([\w ,]+?)\s*-->")
LEFT_TO_REFERENCE = re.compile(r"<!--\s*options left to the reference:\s*([^>]*?)\s*-->")


def reference_options(ref_dir):
    """{command: {long option: short option or None}} of the generated reference."""
    commands = {}
    for name in sorted(os.listdir(ref_dir)):
        if not name.endswith(".md") or name == "index.md":
            continue
        options = {}
        with open(os.path.join(ref_dir, name), encoding="utf-8") as f:
            for line in f:
                m = REF_OPTION.match(line)
                if m and m.group(2) not in ("--help", "--version"):
                    options[m.group(2)] = m.group(1)
        commands[name[:-3]] = options
    return commands


def guide_sections(page):
    """{command: (first line, text)} of the page's level-2 sections that name
    `glyphcast COMMAND`."""
    sections, current = {}, None
    with open(page, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.startswith("## "):
                m = SECTION.match(line)
                current = m.group(1) if m else None
                if current:
                    sections[current] = (number, [])
            elif current:
                sections[current][1].append(line)
    return {c: (n, "".join(lines)) for c, (n, lines) in sections.items()}


def mentions(text, option):
    return option and re.search(r"(?<![\w-])%s(?![\w-])" % re.escape(option), text)


def synopsis_options(command, text):
    """The long options of the section's code-block lines from `glyphcast COMMAND` on
    (and their continuation lines, indented)."""
    found, inside, in_synopsis = set(), False, False
    for line in text.splitlines():
        if FENCE.match(line):
            inside, in_synopsis = not inside, False
            continue
        if not inside:
            continue
        if line.startswith("glyphcast "):
            in_synopsis = line.startswith("glyphcast %s" % command)
        elif not line.startswith(" "):
            in_synopsis = False
        if in_synopsis:
            found.update(re.findall(r"(?<![\w-])--[a-z][\w-]*", line.split("#")[0]))
    return found


def check_cli(page, ref_dir):
    reference = reference_options(ref_dir)
    sections = guide_sections(page)
    problems, count = [], 0
    for command, options in sorted(reference.items()):
        if command not in sections:
            problems.append("%s: no section for `glyphcast %s` (a level-2 heading naming it)" % (page, command))
            continue
        line, text = sections[command]
        borrowed = [c.strip() for m in OPTIONS_OF.findall(text) for c in m.split(",")]
        left = {o for m in LEFT_TO_REFERENCE.findall(text) for o in m.split()}
        for other in borrowed:
            if other not in sections:
                problems.append("%s:%d: glyphcast %s: options of %s: no such section" % (page, line, command, other))
        for option, short in options.items():
            count += 1
            if mentions(text, option) or mentions(text, short) or option in left:
                continue
            if any(other in sections and option in reference.get(other, {})
                   and (mentions(sections[other][1], option) or mentions(sections[other][1], short))
                   for other in borrowed):
                continue
            problems.append("%s:%d: glyphcast %s: %s (in its --help, %s) is not in its section"
                            % (page, line, command, option, os.path.join(ref_dir, command + ".md")))
        for option in sorted(left - set(options)):
            problems.append("%s:%d: glyphcast %s: %s is left to the reference, but the command has no such option"
                            % (page, line, command, option))
        for option in sorted(synopsis_options(command, text) - set(options)):
            problems.append("%s:%d: glyphcast %s: the synopsis names %s, which its --help does not have"
                            % (page, line, command, option))
    return problems, {"commands": len(reference), "options": count}


# settings.md's C API against the header -------------------------------------------------

C_LACKS = re.compile(r"<!--\s*c-api: lacks\s*-->(.*?)<!--\s*/c-api\s*-->", re.S)


def check_settings(page, header):
    with open(page, encoding="utf-8") as f:
        text = f.read()
    with open(header, encoding="utf-8") as f:
        h = f.read()
    struct = re.search(r"typedef struct GlyphcastSettings \{(.*?)\} GlyphcastSettings;", h, re.S)
    if not struct:
        return ["%s: no `typedef struct GlyphcastSettings`" % header], {}
    body = re.sub(r"//[^\n]*", "", struct.group(1))
    fields = set(re.findall(r"(\w+)\s*(?:\[\w*\])?\s*;", body))
    table = re.search(r"<!-- settings table: generated -->(.*?)<!-- end of the settings table -->", text, re.S)
    if not table:
        return ["%s: no generated settings table" % page], {}
    settings = [row.split("|")[1].strip() for row in table.group(1).splitlines()
                if row.startswith("| ") and not row.startswith("| setting |")]
    lacking = {s for s in settings if s.replace(" ", "_") not in fields}
    claims = C_LACKS.findall(text)
    if len(claims) != 1:
        return ["%s: %d `<!-- c-api: lacks -->` paragraphs, want 1" % (page, len(claims))], {}
    said = {m.group(0).strip("`") for m in CODE_SPAN.finditer(claims[0])} & set(settings)
    problems = []
    for s in sorted(said - lacking):
        problems.append("%s: says the C API lacks `%s`, but %s's GlyphcastSettings has the field %s"
                        % (page, s, header, s.replace(" ", "_")))
    for s in sorted(lacking - said):
        problems.append("%s: does not say the C API lacks `%s`, and %s's GlyphcastSettings has no field %s"
                        % (page, s, header, s.replace(" ", "_")))
    words = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five"}
    count = re.match(r"\s*(\w+)", claims[0])
    if count and count.group(1) in words.values() and count.group(1) != words.get(len(lacking)):
        problems.append("%s: says the C API lacks %s settings, the header lacks %d" % (page, count.group(1), len(lacking)))
    return problems, {"settings": len(settings), "fields": len(fields), "lacking": len(lacking)}


def report(problems, summary, what):
    for p in problems:
        print(p)
    if problems:
        print("error: %d problem(s) in %s" % (len(problems), summary), file=sys.stderr)
        return 1
    print("ok: %s, %s" % (summary, what))
    return 0


def main(argv):
    if len(argv) >= 2 and argv[0] == "html" and len(argv) == 3:
        broken, counts = check_html(argv[1], argv[2])
        summary = "%(pages)d pages, %(links)d links (%(repository)d to repository files)" % counts
    elif len(argv) >= 2 and argv[0] == "markdown":
        broken, counts = check_markdown(argv[1:])
        summary = "%(files)d Markdown files, %(links)d links" % counts
    elif len(argv) >= 2 and argv[0] == "generated":
        broken, counts = check_structure(argv[1:])
        summary = "%(files)d generated pages" % counts
        for path, line, text, why in broken:
            print("%s:%d: %s: %s" % (path, line, text, why))
        if broken:
            print("error: %d problem(s) in %s" % (len(broken), summary), file=sys.stderr)
            return 1
        print("ok: %s, one title each and no rustdoc-style link" % summary)
        return 0
    elif len(argv) >= 3 and argv[0] == "figures":
        problems, c = check_figures(argv[1], argv[2:])
        return report(problems, "%(figures)d marked figures of %(measures)d measures" % c,
                      "each as the registry has it")
    elif len(argv) == 3 and argv[0] == "cli":
        problems, c = check_cli(argv[1], argv[2])
        return report(problems, "%(commands)d commands, %(options)d options" % c,
                      "each named in its command's section")
    elif len(argv) == 3 and argv[0] == "settings":
        problems, c = check_settings(argv[1], argv[2])
        return report(problems, "%s against %s" % (argv[1], argv[2]),
                      "the C API's settings as the header has them")
    else:
        sys.stderr.write(__doc__)
        return 2
    for path, line, url, why in broken:
        print("%s:%d: %s: %s" % (path, line, url, why))
    if broken:
        print("error: %d broken link(s) in %s" % (len(broken), summary), file=sys.stderr)
        return 1
    print("ok: %s, all resolve" % summary)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
