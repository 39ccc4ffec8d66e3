"""present — the report's presentation: reads what build/report measured (CSV, run.json) and
writes docs/report.md with its plots. Entry point: bench/report.py."""
