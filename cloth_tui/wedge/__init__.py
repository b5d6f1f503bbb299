"""Wedges: one scene run over every combination of a few varied keys, each run a task on a
Dask cluster (local processes by default, or a scheduler given by address), gathered into a
labelled contact sheet and a table. The accuracy study sends its runs through the same engine.

plan (what to run, validated up front) → engine (Dask: submit, progress, retries, cancel)
→ task (on a worker: simulate, render a thumbnail) → sheet (the labelled grid, PNG or MP4).
"""
