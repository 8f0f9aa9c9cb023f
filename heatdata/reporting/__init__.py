"""What a person reads: figures (split by chapter) and the report's pages."""
