#!/usr/bin/env python3
"""Every public symbol of libwave's headers has a page in the API reference.

Doxygen only warns about an undocumented member of something it documents: the members
of an undocumented namespace or file are dropped from the reference without a word (the
reference once had no page for any free function and 0 warnings). So this check does not
trust what Doxygen chose to show. It runs Doxygen a second time on the same headers with
EXTRACT_ALL = YES and XML output only, which lists every symbol the headers declare, and
fails, naming each symbol and its header, when one

  * has no description (neither brief nor detailed), or
  * has no page in the HTML reference: no page for the namespace, class or header, or no
    anchor for the member on its compound's page.

Symbols: the namespace wave and the namespaces in it (wave::detail and what is inside it
excepted, as the Doxyfile's EXCLUDE_SYMBOLS), their functions, variables, typedefs, enums
and classes/structs/unions; the public members of those classes; the public headers and
their macros. Enumerators need a page, their description may be the enum's.

usage: reference_coverage.py DOXYGEN DOCS_DIR   (DOCS_DIR: <build>/docs, the Doxyfile's
and the reference's folder; run after Doxygen built the reference there)
Standard library only.
"""
import collections
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

# What the audit run changes in the reference's own Doxyfile (read with @INCLUDE).
AUDIT_CONFIG = """
@INCLUDE = {doxyfile}
EXTRACT_ALL = YES
GENERATE_HTML = NO
GENERATE_XML = YES
OUTPUT_DIRECTORY = {out}
WARN_IF_UNDOCUMENTED = NO
WARN_AS_ERROR = NO
WARN_LOGFILE = {out}/doxygen-warnings.log
QUIET = YES
"""

MEMBER_KINDS = {"function", "variable", "typedef", "enum", "define"}
CLASS_KINDS = {"class", "struct", "union"}


def text(element):
    return "".join(element.itertext()).strip() if element is not None else ""


def described(element):
    return bool(text(element.find("briefdescription")) or text(element.find("detaileddescription")))


def internal(qualified_name):
    return "detail" in qualified_name.split("::")


def header_of(element):
    location = element.find("location")
    if location is None:
        return "?"
    return location.get("declfile") or location.get("file") or "?"


class Html:
    """The anchors of the HTML reference's pages, read once per page."""

    def __init__(self, folder):
        self.folder = folder
        self.anchors = {}

    def page(self, compound_id):
        return os.path.isfile(os.path.join(self.folder, compound_id + ".html"))

    def anchor(self, member_id):
        compound_id, anchor = member_id.rsplit("_1", 1)
        if compound_id not in self.anchors:
            path = os.path.join(self.folder, compound_id + ".html")
            found = set()
            if os.path.isfile(path):
                with open(path, encoding="utf-8") as f:
                    found = set(re.findall(r'\bid="([^"]+)"', f.read()))
            self.anchors[compound_id] = found
        return anchor in self.anchors[compound_id]


def main(doxygen, docs_dir):
    docs_dir = os.path.abspath(docs_dir)
    doxyfile = os.path.join(docs_dir, "Doxyfile")
    out = os.path.join(docs_dir, "reference-audit")
    os.makedirs(out, exist_ok=True)
    run = subprocess.run([doxygen, "-"], input=AUDIT_CONFIG.format(doxyfile=doxyfile, out=out),
                         text=True, cwd=docs_dir, capture_output=True)
    if run.returncode != 0:
        sys.exit(f"reference_coverage: the audit run of Doxygen failed ({run.returncode}):\n{run.stdout}{run.stderr}")
    xml_dir = os.path.join(out, "xml")
    html = Html(os.path.join(docs_dir, "reference", "html"))

    missing = []  # (header, symbol, kind, what is wrong)
    counted = collections.Counter()

    def check(element, name, kind, header, need_description=True, page_of=None):
        ident = element.get("id")
        problems = []
        if need_description and not described(element):
            problems.append("no description")
        on_page = html.page(ident) if page_of is None else html.anchor(ident)
        if not on_page:
            problems.append("no page" if page_of is None else f"no anchor on {page_of}.html")
        if problems:
            missing.append((header, name, kind, ", ".join(problems)))
        else:
            counted[kind] += 1

    index = ET.parse(os.path.join(xml_dir, "index.xml")).getroot()
    for compound in index.findall("compound"):
        kind = compound.get("kind")
        if kind not in {"namespace", "file"} | CLASS_KINDS:
            continue
        root = ET.parse(os.path.join(xml_dir, compound.get("refid") + ".xml")).getroot()
        for cdef in root.findall("compounddef"):
            name = text(cdef.find("compoundname"))
            if kind == "file":
                if not name.endswith(".h"):
                    continue
                header = header_of(cdef)
                check(cdef, name, "header", header)
                # Only the macros: the rest of a header's members are its namespace's.
                for mdef in cdef.iter("memberdef"):
                    if mdef.get("kind") == "define":
                        check(mdef, text(mdef.find("name")), "macro", header, page_of=cdef.get("id"))
                continue
            if not (name == "wave" or name.startswith("wave::")) or internal(name):
                continue
            if kind in CLASS_KINDS and cdef.get("prot") != "public":
                continue
            header = header_of(cdef)
            check(cdef, name, kind, header)
            for section in cdef.findall("sectiondef"):
                if kind in CLASS_KINDS and not section.get("kind").startswith("public"):
                    continue
                for mdef in section.findall("memberdef"):
                    mkind = mdef.get("kind")
                    if mkind not in MEMBER_KINDS or mdef.get("prot", "public") != "public":
                        continue
                    qualified = text(mdef.find("qualifiedname")) or f"{name}::{text(mdef.find('name'))}"
                    if internal(qualified):
                        continue
                    label = ("free " if kind == "namespace" else "member ") + mkind
                    check(mdef, qualified + text(mdef.find("argsstring")), label, header_of(mdef),
                          page_of=cdef.get("id"))
                    for value in mdef.findall("enumvalue"):
                        check(value, f"{qualified}::{text(value.find('name'))}", "enumerator",
                              header_of(mdef), need_description=False, page_of=cdef.get("id"))

    for kind, n in sorted(counted.items()):
        print(f"{n:5d} {kind} with a page")
    if counted["free function"] == 0:
        missing.append(("?", "wave", "namespace", "no free function found at all"))
    if missing:
        print(f"\n{len(missing)} public symbol(s) of the headers without a page or a description "
              "in the API reference:", file=sys.stderr)
        for header, name, kind, problem in sorted(missing):
            print(f"  {header}: {kind} {name}: {problem}", file=sys.stderr)
        return 1
    print("every public symbol of the headers has a described page in the API reference")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
