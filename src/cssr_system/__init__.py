"""cssr_system: the animateBehaviour node of the CSSR4Africa project and its algorithms."""
