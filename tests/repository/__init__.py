"""The repository's invariants: the import layers, declared dependencies, links in the docs, the committed
schema, CI running the README's command, a clone that stands alone, plugin discovery."""
