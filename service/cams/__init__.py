"""/v1/cams: barrel, parallel indexing and roller-gear cams (one module per cam type)."""
