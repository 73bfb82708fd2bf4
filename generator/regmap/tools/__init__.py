"""Field tools: what an engineer at a drive uses (frame, decode, read/write/dump, show), apart from the compiler core."""
