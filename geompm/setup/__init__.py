"""A validated case made into a Scene before any step: particles seeded in body shapes (``bodies.py``), release
bodies from GIS files (``release.py``), geostatic stress and the checks that need particles (``assemble.py``).
Nothing here compiles a kernel."""
