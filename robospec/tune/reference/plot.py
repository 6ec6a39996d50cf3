"""``robospec tune --reference ... --plot DIR``: ``DIR/<uid>/reference.png``, a panel per joint
with the commanded target, the measured position and the simulated one before and after the
fit. matplotlib draws with its Agg backend: no display needed."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from robospec.tune.reference.worker import Outcome

COLUMNS = 3


def plot_reference(folder: Path, uid: str, outcome: Outcome) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    reference, fit = outcome.reference, outcome.fit
    assert reference is not None and fit is not None
    n = len(reference.joints)
    rows = (n + COLUMNS - 1) // COLUMNS
    columns = min(n, COLUMNS)
    figure = Figure(figsize=(4.5 * columns, 2.8 * rows), layout="constrained")
    axes = figure.subplots(rows, columns, squeeze=False)
    t = reference.t - reference.t[0]
    for k, joint in enumerate(reference.joints):
        ax = axes[k // COLUMNS][k % COLUMNS]
        ax.step(t, reference.target[:, k], where="post", color="0.6", ls="--", label="target")
        ax.plot(t, reference.qpos[:, k], color="black", lw=2, label="reference")
        if fit.simulated_before is not None:
            ax.plot(t, fit.simulated_before[:, k], color="tab:red", label="before")
        if fit.simulated_after is not None:
            ax.plot(t, fit.simulated_after[:, k], color="tab:blue", label="after")
        ax.set_title(
            f"{joint}: {fit.errors_before[k]:.1%} -> {fit.errors_after[k]:.1%}", fontsize=9
        )
        ax.set_xlabel("t (s)")
    for k in range(n, rows * columns):
        axes[k // COLUMNS][k % COLUMNS].set_visible(False)
    axes[0][0].legend(fontsize=7)
    figure.suptitle(f"{uid}: fitted to {reference.source}")
    path = folder / uid / "reference.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, staging = tempfile.mkstemp(prefix=".robospec-", suffix=".png", dir=path.parent)
    os.close(handle)
    try:
        figure.savefig(staging, format="png", dpi=90)
        os.chmod(staging, 0o644)
        os.replace(staging, path)
    except BaseException:
        Path(staging).unlink(missing_ok=True)
        raise
    return path
