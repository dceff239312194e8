"""peridynamics package."""
