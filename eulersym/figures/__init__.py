"""Pictures of the motion a physicist draws (placeholder, filled below)."""
