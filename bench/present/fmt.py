"""fmt.py — how numbers and tables are written in the report: 3 significant digits, milliseconds,
ratios, percentages, markdown tables. One place, so every table and sentence agrees."""
import math


def finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x)


def g3(x):
    """3 significant digits; exponent form below 1e-4 and from 1e6."""
    if not finite(x):
        return "n/a"
    if x == 0:
        return "0"
    if abs(x) < 1e-4 or abs(x) >= 1e6:
        return "%.2e" % x
    return "%.3g" % x


def ms(x):
    if not finite(x):
        return "n/a"
    if x >= 100:
        return "%.0f" % x
    return "%.3g" % x if x >= 0.001 else "%.2g" % x


def ratio(x):
    """A factor: 2 significant digits below 0.1, 2 decimals below 10, 1 below 100, none above (no ×
    sign: the prose adds it)."""
    if not finite(x) or x <= 0:
        return "n/a"
    if x >= 100:
        return "%.0f" % x
    if x < 0.1:
        return "%.2g" % x
    return "%.1f" % x if x >= 10 else "%.2f" % x


def over(a, b):
    """a / b, or None when either is missing or b is 0."""
    return a / b if finite(a) and finite(b) and b != 0 else None


def pct(x, digits=2):
    """A fraction as a percentage."""
    return "n/a" if not finite(x) else "%.*f %%" % (digits, 100 * x)


def listing(items, empty="none"):
    items = list(items)
    return ", ".join(items) if items else empty


def table(head, rows, align=None):
    """A markdown table; align: one of 'l' or 'r' per column (default: first left, rest right)."""
    align = align or ["l"] + ["r"] * (len(head) - 1)
    out = ["| " + " | ".join(head) + " |", "|" + "|".join("---" if a == "l" else "--:" for a in align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"
