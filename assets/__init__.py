"""Built-in scenes (scenes/*.toml) and textures (textures/*.png). Installed as the package
`cloth_tui.assets` (see pyproject.toml); code finds these files through cloth_tui/resources.py."""
