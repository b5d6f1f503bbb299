"""Where the built-in scenes and textures are: the one place that finds `assets/`.

`assets/` sits at the top of the repository and is installed as the package
`cloth_tui.assets` (pyproject.toml maps one to the other). In a source checkout (an editable
install, or PYTHONPATH pointing at it) the checkout's own `assets/` is used, so a change to a
scene shows at once; in an installed wheel, `importlib.resources` finds the packaged copy.
"""

from __future__ import annotations

import functools
import importlib.resources
from pathlib import Path

ASSETS_PACKAGE = "cloth_tui.assets"


@functools.cache
def assets_dir() -> Path:
    checkout = Path(__file__).resolve().parent.parent
    if (checkout / "pyproject.toml").is_file() and (checkout / "assets" / "scenes").is_dir():
        return checkout / "assets"
    return installed_assets_dir()


def installed_assets_dir() -> Path:
    """The packaged copy, as installed from a wheel."""
    try:
        root = importlib.resources.files(ASSETS_PACKAGE)
    except ModuleNotFoundError:
        raise FileNotFoundError("cloth-tui's built-in scenes are missing: no assets/ beside "
                                "the package and no cloth_tui.assets installed; reinstall "
                                "cloth-tui") from None
    if not isinstance(root, Path):  # e.g. imported from a zip: the files must be on disk
        raise FileNotFoundError(f"cloth-tui's assets are not files on disk ({root}); "
                                "install cloth-tui unpacked (pip install)")
    return root


def scenes_dir() -> Path:
    return assets_dir() / "scenes"


def textures_dir() -> Path:
    return assets_dir() / "textures"


def builtin_scenes() -> dict[str, Path]:
    """Built-in scene name → its TOML file, sorted by name."""
    return {p.stem: p for p in sorted(scenes_dir().glob("*.toml"))}
