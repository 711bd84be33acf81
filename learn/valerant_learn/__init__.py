"""Training code for valerant's learned monocular depth prior (see learn/README.md)."""
