"""style.py — each method's colour and marker in the plots. A method not listed here gets the
next colour of matplotlib's cycle and a circle: adding a method to bench/plan.c needs no edit."""

METHODS = {
    "constant": ("#9a9a9a", "v"),
    "linear": ("#1f5fbf", "o"),
    "linear4": ("#3fa7c9", "s"),
    "clough-tocher": ("#d62728", "o"),
    "ct-free": ("#ff9896", "o"),
    "ct-salesin": ("#ff8c1a", "^"),
    "ct-affine": ("#e377c2", "D"),
    "ct-literal": ("#8c564b", "s"),
    "clough-tocher-c1": ("#7b3fb0", "o"),
    "ct-given": ("#2ca02c", "*"),
    "ct-estimate": ("#b8930b", "P"),
    "ct-estimate-free": ("#e0c060", "P"),
    "powell-sabin": ("#17becf", "x"),
    "hermite": ("#000000", "s"),
    "hermite-zero-twist": ("#6b6b6b", "D"),
}
_CYCLE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]


def style(name, index=0):
    """(colour, marker) of method name; index picks the cycle's colour for unlisted ones."""
    return METHODS.get(name, (_CYCLE[index % len(_CYCLE)], "o"))
