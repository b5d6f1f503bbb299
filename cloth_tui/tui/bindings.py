"""The app's keys, by group. Global keys are priority bindings so a focused widget cannot
swallow them; `ClothApp.check_action` hands them back to a focused control that needs them.
The help screen (help.py) lists these groups, so a key is described once, here; the footer
shows the few keys that fit 80 columns (`?` lists the rest)."""

from textual.binding import Binding

BUMP_M = 0.05  # how far one arrow / PageUp / PageDown press pushes a particle, metres
ORBIT_DEG = 10.0
ZOOM_STEP = 1.25
VIEW_SPAN = 2.5  # rough height of the default view, in cloth sizes (for mouse drags)
# Actions a focused text field or open dropdown keeps for itself (it needs those keys).
TEXT_KEYS_ACTIONS = {"quit", "pause", "restart", "toggle", "screenshot", "video", "bake",
                     "save_scene",
                     "toggle_controls", "bump", "crosshair", "orbit", "zoom", "reset_camera",
                     "one_thread", "help", "pin"}
# Actions whose key a focused control (switch, button, dropdown, group title) acts on.
CONTROL_KEYS_ACTIONS = {"pause"}  # space toggles a switch, presses a button, opens a group


def key(keys: str, action: str, label: str, help: str, *, show: bool = True,
        key_display: str | None = None) -> Binding:
    """An app key: `label` is the footer's word, `help` the help screen's sentence."""
    return Binding(keys, action, label, show=show, key_display=key_display, priority=True,
                   tooltip=help)


KEY_GROUPS: dict[str, list[Binding]] = {
    "Simulation": [
        key("space", "pause", "Pause", "pause or run the simulation (when no control has "
            "focus; on a switch, space toggles it)"),
        key("r", "restart", "Restart", "start the sheet again from its rest shape, held by "
            "the scene's pins alone"),
        key("t", "one_thread", "One thread", "physics on one thread, or back to the measured "
            "choice of one or two (as CLOTH_TUI_THREADS=1 does for a whole run)", show=False),
        key("q", "quit", "Quit", "quit (a running video is finished first)"),
    ],
    "Look and panels": [
        key("w", "toggle('appearance.wireframe')", "Wireframe", "wireframe or solid cloth",
            show=False),
        key("a", "toggle('appearance.auto_rotate')", "Auto-rotate",
            "orbit the camera by itself", show=False),
        key("c", "toggle_controls", "Controls", "show or hide the controls (a drawer on a "
            "narrow terminal)"),
        key("question_mark,f1", "help", "Help", "this list of keys and mouse actions",
            key_display="?"),
    ],
    "Captures": [
        key("i", "screenshot", "Screenshot", "save a PNG of the view to the captures folder"),
        key("v", "video", "Record", "start or stop recording an MP4 video"),
        key("e", "bake", "Bake USD", "start or stop recording the sheet to a USD file",
            show=False),
        key("s", "save_scene", "Save scene", "save the current settings as a scene TOML file",
            show=False),
    ],
    "Camera": [
        key("left_square_bracket", "orbit(-1, 0)", "Orbit left", "orbit the camera left",
            show=False),
        key("right_square_bracket", "orbit(1, 0)", "Orbit right", "orbit the camera right",
            show=False),
        key("comma", "orbit(0, -1)", "Orbit down", "orbit the camera down", show=False),
        key("full_stop", "orbit(0, 1)", "Orbit up", "orbit the camera up", show=False),
        key("plus,equals_sign", "zoom(1)", "Zoom in", "zoom in", show=False),
        key("minus", "zoom(-1)", "Zoom out", "zoom out", show=False),
        key("o", "reset_camera", "Reset view", "put the camera back where it started",
            show=False),
    ],
    "Push the cloth": [
        key("up", "bump(0, 1, 0)", "Bump up", "push the particle under the pointer (or the "
            "crosshair) up", show=False),
        key("down", "bump(0, -1, 0)", "Bump down", "push it down", show=False),
        key("left", "bump(-1, 0, 0)", "Bump left", "push it left", show=False),
        key("right", "bump(1, 0, 0)", "Bump right", "push it right", show=False),
        key("pageup", "bump(0, 0, 1)", "Bump +z", "push it towards the viewer (+z)", show=False),
        key("pagedown", "bump(0, 0, -1)", "Bump -z", "push it away (-z)", show=False),
        key("h,shift+left", "crosshair(-1, 0)", "Crosshair left",
            "move the crosshair left (without a mouse)", show=False),
        key("l,shift+right", "crosshair(1, 0)", "Crosshair right", "move the crosshair right",
            show=False),
        key("k,shift+up", "crosshair(0, -1)", "Crosshair up", "move the crosshair up",
            show=False),
        key("j,shift+down", "crosshair(0, 1)", "Crosshair down", "move the crosshair down",
            show=False),
        key("p", "pin", "Pin", "pin the particle under the pointer (or the crosshair) where it "
            "is, as Ctrl+drag does (r restores the scene's pins)", show=False),
    ],
}

APP_BINDINGS = [b for group in KEY_GROUPS.values() for b in group] + [
    Binding("escape", "unfocus", "Leave field", show=False),
]

# What the mouse does (Preview's handlers); keys of the fields are their widgets' bindings.
MOUSE_ACTIONS = [
    ("drag on the cloth", "grab the particle under the pointer and pull it"),
    ("Ctrl+drag on the cloth", "pull a particle and pin it where you let go (r restores "
     "the scene's pins)"),
    ("right-drag on the cloth", "cut it along the path (the torn count shows; r heals)"),
    ("pointer over the view", "arrows and PageUp/PageDown push the particle under it"),
    ("click a field", "edit it; hover a setting for its description"),
    ("click a group title", "open or close the group"),
]
# How fields take keys (Textual's Input, Switch and Select, and SettingField).
FIELD_KEYS = [
    ("Tab / Shift+Tab", "next / previous control"),
    ("Enter", "apply the value and move to the next field"),
    ("Escape", "restore the last good value and leave the field"),
    ("space / Enter", "toggle a focused switch; open a focused dropdown"),
]
