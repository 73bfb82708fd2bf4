"""Back ends: each reads only the `Device` model and writes one kind of output."""
