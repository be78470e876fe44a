"""The pieces of scripts/fault_table.py: harness (running children, classifying what they did),
checks (file snapshots and message checks) and cases_* (the faults, by theme)."""
