"""/v1/motions: motion programs (specs, the bridge to camcore.motion, routes)."""
