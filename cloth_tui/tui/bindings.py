"""The app's keys. Global keys are priority bindings so a focused widget cannot swallow
them; `ClothApp.check_action` hands them back to a focused text field or open dropdown."""

from textual.binding import Binding

BUMP_M = 0.05  # how far one arrow / PageUp / PageDown press pushes a particle, metres
ORBIT_DEG = 10.0
ZOOM_STEP = 1.25
VIEW_SPAN = 2.5  # rough height of the default view, in cloth sizes (for mouse drags)
# Actions a focused text field or open dropdown keeps for itself (it needs those keys).
TEXT_KEYS_ACTIONS = {"quit", "pause", "restart", "toggle", "screenshot", "video", "bake", "save_scene",
                     "toggle_controls", "bump", "crosshair", "orbit", "zoom", "reset_camera",
                     "one_thread"}

APP_BINDINGS = [
    Binding("q", "quit", "Quit", priority=True),
    Binding("space", "pause", "Pause", priority=True),
    Binding("r", "restart", "Restart", priority=True),
    Binding("w", "toggle('appearance.wireframe')", "Wire", priority=True),
    Binding("a", "toggle('appearance.auto_rotate')", "Rotate", priority=True),
    Binding("i", "screenshot", "Shot", priority=True),
    Binding("v", "video", "Video", priority=True),
    Binding("e", "bake", "Bake USD", priority=True, show=False),
    Binding("s", "save_scene", "Save", priority=True),
    Binding("c", "toggle_controls", "Controls", priority=True),
    Binding("t", "one_thread", "One thread", priority=True, show=False),
    Binding("up", "bump(0, 1, 0)", "Bump", priority=True, key_display="←↑↓→⇞⇟"),
    Binding("down", "bump(0, -1, 0)", "Bump down", priority=True, show=False),
    Binding("left", "bump(-1, 0, 0)", "Bump left", priority=True, show=False),
    Binding("right", "bump(1, 0, 0)", "Bump right", priority=True, show=False),
    Binding("pageup", "bump(0, 0, 1)", "Bump +z", priority=True, show=False),
    Binding("pagedown", "bump(0, 0, -1)", "Bump -z", priority=True, show=False),
    Binding("h,shift+left", "crosshair(-1, 0)", "Cursor", priority=True,
            key_display="hjkl"),
    Binding("l,shift+right", "crosshair(1, 0)", "Crosshair right", priority=True,
            show=False),
    Binding("k,shift+up", "crosshair(0, -1)", "Crosshair up", priority=True, show=False),
    Binding("j,shift+down", "crosshair(0, 1)", "Crosshair down", priority=True,
            show=False),
    Binding("left_square_bracket", "orbit(-1, 0)", "Orbit", priority=True,
            key_display="[ ] , ."),
    Binding("right_square_bracket", "orbit(1, 0)", "Orbit right", priority=True,
            show=False),
    Binding("comma", "orbit(0, -1)", "Orbit down", priority=True, show=False),
    Binding("full_stop", "orbit(0, 1)", "Orbit up", priority=True, show=False),
    Binding("plus,equals_sign", "zoom(1)", "Zoom", priority=True, key_display="+ -"),
    Binding("minus", "zoom(-1)", "Zoom out", priority=True, show=False),
    Binding("0", "reset_camera", "Reset view", priority=True, show=False),
    Binding("escape", "unfocus", "Leave field", show=False),
]
