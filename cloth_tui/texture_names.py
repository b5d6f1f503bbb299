"""The names of the built-in textures, in a module of its own so that the scene schema can
check a texture setting without importing the render package that draws them."""

BUILTIN_TEXTURES = ("maze", "grass")
