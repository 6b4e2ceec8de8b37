"""Benchmark suite: ``python -m bench`` prints one JSON object of ratio figures.

See bench/README.md for what each figure measures and its target.
"""
