#!/usr/bin/python3
"""The docs test (CTest label `docs`): README.md and docs/ name nothing outside the repository,
nor do the files the pages send users to run or read (sweeps/, examples/, jobs/, src/post/),
whose scripts with a #! line are executable as the pages invoke them; the README's relative
links resolve, docs/spec.md documents every key the spec parser accepts,
and `mkdocs build --strict` passes (a broken link between
pages, or a page missing from the nav that is linked, fails it).

Usage: check_docs.py SOURCE_DIR SITE_DIR
"""
import pathlib
import re
import subprocess
import sys

# Names of files that are not in a clone, and ways of pointing outside it.
FORBIDDEN = [
    (re.compile(r"shared/"), "a path under shared/ (not in the repository)"),
    (re.compile(r"INTERFACE\.md"), "INTERFACE.md (not in the repository)"),
    (re.compile(r"PHYSICS\.md"), "PHYSICS.md (not in the repository)"),
    (re.compile(r"\.\./"), "a path with ../ (outside the page's folder)"),
    (re.compile(r"\bissue \d+", re.IGNORECASE), "an issue number (issues are not in the repository)"),
    (re.compile(r"/work/"), "a path of the machine it was written on"),
]
LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def pages(root):
    yield root / "README.md"
    yield from sorted((root / "docs").glob("*.md"))


def user_files(root):
    """What the pages tell users to run or read beside them: the specs, the example, the batch
    jobs and the post-processing scripts. Their comments are read as documentation too."""
    for folder, pattern in (("sweeps", "*.toml"), ("examples", "*"), ("jobs", "*"),
                            ("src/post", "*.py")):
        yield from sorted(p for p in (root / folder).glob(pattern) if p.is_file())


# Scripts with a #! line that are not run but sourced or imported by the others.
NOT_RUN = {"jobs/machine_facts.sh",    # sourced by jobs/bench_*.sh
           "src/post/safe_output.py"}  # imported by the plot scripts


def not_executable(root, path):
    """A script with a #! line that cannot be run as `path ARGS` (the pages invoke them so)."""
    if path.relative_to(root).as_posix() in NOT_RUN:
        return False
    with open(path, "rb") as f:
        shebang = f.read(2) == b"#!"
    return shebang and not path.stat().st_mode & 0o111


def broken_anchors(docs, site):
    """Links page.md#anchor (or #anchor) whose anchor is no id in the built page: this MkDocs
    (1.4) checks the pages, not the anchors."""
    ids = {}
    for html in site.rglob("index.html"):
        page = html.parent.relative_to(site).as_posix()
        ids[page if page != "." else "index"] = set(re.findall(r'id="([^"]+)"', html.read_text(encoding="utf-8")))
    errors = []
    for md in sorted(docs.glob("*.md")):
        for target in LINK.findall(md.read_text(encoding="utf-8")):
            if "#" not in target or re.match(r"[a-z]+://", target):
                continue
            page, anchor = target.split("#", 1)
            name = page[:-3] if page else md.stem
            if name not in ids:
                continue  # a missing page is mkdocs's to report
            if anchor not in ids[name]:
                errors.append(f"docs/{md.name}: link to {target}: no heading with that anchor")
    return errors


def parser_keys(root):
    """Every key the spec parser accepts by name: the lists it checks tables against
    (check_keys, measure_settings), the sections and the measures (spec_names.hpp,
    spec_reader.hpp). Scene parameters and variables come from the catalogs instead."""
    keys = set()
    for source in sorted((root / "src" / "io").glob("spec_*.[ch]pp")):
        text = source.read_text(encoding="utf-8")
        for call in re.finditer(r"(?:check_keys|measure_settings)\((.*?)\);", text, re.DOTALL):
            for braces in re.findall(r"\{([^{}]*)\}", call.group(1)):
                keys.update(re.findall(r'"([a-z_]+)"', braces))
        for listed in re.findall(r"k(?:Sections|MeasureNames)\[\] = \{([^}]*)\}", text):
            keys.update(re.findall(r'"([a-z_]+)"', listed))
    keys.update({"title", "name", "K", "label"})  # read by name in spec_scene.cpp
    return keys


def undocumented_keys(root):
    spec = (root / "docs" / "spec.md").read_text(encoding="utf-8")
    keys = parser_keys(root)
    errors = [f"docs/spec.md does not document the key `{key}` that the parser accepts"
              for key in sorted(keys) if f"`{key}`" not in spec and f"[{key}]" not in spec]
    if len(keys) < 30:  # the extraction itself broke: fail rather than check nothing
        errors.append(f"found only {len(keys)} parser keys in src/io/spec_*.cpp: {sorted(keys)}")
    return errors


def main():
    root, site = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    errors = []
    for page in pages(root):
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            for pattern, what in FORBIDDEN:
                if pattern.search(line):
                    errors.append(f"{page.relative_to(root)}:{number}: names {what}: {line.strip()}")
    for path in user_files(root):
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for pattern, what in FORBIDDEN:
                if pattern.search(line):
                    errors.append(f"{path.relative_to(root)}:{number}: names {what}: {line.strip()}")
        if not_executable(root, path):
            errors.append(f"{path.relative_to(root)}: has a #! line but is not executable")
    errors += undocumented_keys(root)
    readme = root / "README.md"
    for target in LINK.findall(readme.read_text(encoding="utf-8")):
        if re.match(r"[a-z]+://|#|mailto:", target):
            continue
        if not (root / target.split("#")[0]).exists():
            errors.append(f"README.md: link to {target}, which is not in the repository")
    if (root / "docs" / "figures").resolve() != (root / "sweeps" / "figures").resolve():
        errors.append("docs/figures must be the link to sweeps/figures the pages' images use")
    build = subprocess.run(["mkdocs", "build", "--strict", "--clean", "--site-dir", str(site)],
                           cwd=root, capture_output=True, text=True)
    if build.returncode != 0:
        errors.append("mkdocs build --strict failed:\n" + build.stdout + build.stderr)
    elif not (site / "spec" / "index.html").exists():
        errors.append(f"mkdocs build wrote no spec page under {site}")
    else:
        errors += broken_anchors(root / "docs", site)
    for error in errors:
        print(error)
    print(f"check_docs: {len(errors)} problem(s)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
