"""Pictures in the terminal: kitty graphics and sixel encoders, half-block dithering and the
terminal detection; pure Python and NumPy, no Textual (tested alone)."""
