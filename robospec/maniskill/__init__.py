"""The ManiSkill installed beside robospec, on the floor just above the diagnostics: which one it
is and what it registers, read from its files without importing it (:mod:`.installed`,
:mod:`.builtin_uids`, :mod:`.tasks`), and what its scenes give every robot (:mod:`.scenes`);
loading robots where SAPIEN finds no render device (:mod:`.render_fallback`, :mod:`.headless`);
and what it prints, told once (:mod:`.upstream_output`). Stages from ``pipeline`` up use it;
the tools that run ManiSkill (check, tune, optimize, new's probes) import ManiSkill itself where
they run it."""
