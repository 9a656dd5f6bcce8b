"""What users receive: videos, drawings, plot sheets, CSV/JSON/TOML files and display units."""
