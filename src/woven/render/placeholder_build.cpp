// Removed once the sim module has sources.
