"""Rolling noise: CNOSSOS-EU source model and the physics-based (TWINS-like) chain from this project's models."""
