"""mpm package."""
