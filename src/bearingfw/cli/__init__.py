"""Command-line interface (the top layer: it may import every other one)."""
