#!/usr/bin/env python3
"""table.py — turns the stability suite's TSV (TC_STABILITY_TABLE=FILE build/test_unit) into the
markdown table of docs/stability.md, replacing what lies between its two marker lines.

    /usr/bin/python3 tests/stability/table.py TABLE.tsv docs/stability.md
"""
import csv
import sys

BEGIN, END = "<!-- stability-table:begin -->", "<!-- stability-table:end -->"
COLUMNS = [("constant", "const"), ("linear", "lin"), ("linear4", "lin4"),
           ("clough-tocher/normal/corrected", "ct"), ("clough-tocher/salesin/corrected", "ct-s"),
           ("clough-tocher/affine/corrected", "ct-a"), ("clough-tocher/normal/literal", "ct-lit"),
           ("clough-tocher/salesin/literal", "ct-s-lit"), ("clough-tocher-c1/normal", "ct-c1"),
           ("powell-sabin", "ps"), ("hermite", "herm")]
MARK = {"exempt": " x", "info": "", "pass": "", "pass+refused": " r", "refused": "R"}


def cell(row):
    verdict = row["verdict"]
    if verdict == "refused":
        return "R"
    if verdict.startswith("FAIL"):
        return "**%s %s**" % (fmt(row["worst"]), verdict)
    return fmt(row["worst"]) + MARK.get(verdict, " ?")


def fmt(s):
    try:
        v = float(s)
    except ValueError:
        return s
    return "0" if v == 0 else "%.2g" % v


def table(rows):
    order, cells = [], {}
    for r in rows:
        key = (r["case"], r["measure"], r["bound"])
        if key not in cells:
            order.append(key)
            cells[key] = {}
        cells[key][r["method"]] = cell(r)
    out = ["| case | measure | bound | " + " | ".join(c[1] for c in COLUMNS) + " |",
           "|---|---|---|" + "---|" * len(COLUMNS)]
    for key in order:
        out.append("| %s | %s | %s | " % (key[0], key[1].replace("|", "\\|"), key[2]) +
                   " | ".join(cells[key].get(c[0], "–") for c in COLUMNS) + " |")
    return "\n".join(out)


def main():
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    unknown = sorted({r["method"] for r in rows} - {c[0] for c in COLUMNS})
    if unknown:  # a variant added to stab_var (tests/stability/stab.c) needs a column here
        sys.exit("table.py: no column for the variants %s: add them to COLUMNS" % ", ".join(unknown))
    doc = open(sys.argv[2]).read()
    a, b = doc.index(BEGIN) + len(BEGIN), doc.index(END)
    with open(sys.argv[2], "w") as f:
        f.write(doc[:a] + "\n" + table(rows) + "\n" + doc[b:])


if __name__ == "__main__":
    main()
