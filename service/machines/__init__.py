"""Machines: several axes on one camshaft (POST /v1/machines)."""
