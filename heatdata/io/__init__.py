"""Files to data: 3D models, catalogues (CSV, Sweet Home 3D), Parquet tables and MakeHuman bodies."""
