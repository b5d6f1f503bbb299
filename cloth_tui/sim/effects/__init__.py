"""What acts on the sheet besides its solver: forces, impulses, pins, tearing, and the stages
the pipeline shares."""
