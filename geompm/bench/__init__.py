"""``geompm bench``: the standard scenes, each timed in a fresh process (``worker.py``), streamed (``stream.py``)."""
