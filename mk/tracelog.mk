# --- trace logs and rttrace (docs/tracer-log.md) ---
