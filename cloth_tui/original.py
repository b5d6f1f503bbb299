"""What the original assignment fixed that this program keeps as a reference: its step. The
`damping` key is a share of velocity lost per this interval, whatever the substeps. A leaf
module: the scene schema and the physics both read it."""

ORIGINAL_TIMESTEP = 0.018  # s: the original's fixed step
