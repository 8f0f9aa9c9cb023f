"""heatdata's version, in one place (read by pyproject.toml, the tables' metadata and the CLI)."""

__version__ = "0.1.0"
