"""`robospec lsp`: a Language Server for spec files (pygls, the ``lsp`` extra).

server (the LSP features, debounced publishing), documents (each open spec's unsaved text and
its compilation, descriptions parsed once per change), positions (cursor -> key path, YAML and
TOML), schema_paths (what the JSON Schema allows there), robot (names and facts of the robot),
completion, hover and definition. Light core only: nothing here imports ManiSkill, SAPIEN or
torch.
"""
