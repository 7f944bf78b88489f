"""What every layer of camdyn shares: its errors, units and defaults, output files and the traced-program cache."""
