// Removed once the geometry module has sources.
