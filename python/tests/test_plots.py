"""Every result's .plot() (issue 46): rendered to PNG and checked for what a reader needs: the
image is not empty, every axis is labelled with its unit, each series has its own colour, and
without matplotlib the call says how to install it."""
import os
import sys

import numpy as np
import pytest

import gmwm
from cli_support import SOURCE, run, write_fleet

matplotlib = pytest.importorskip("matplotlib", reason="python3-matplotlib (tools/setup.sh installs it)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TRUTH = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-11)"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# A rendered 7 x 4.5 inch plot at 80 dpi with data on it is tens of kilobytes; an empty
# frame with labels is under 12 kB.
MIN_PNG_BYTES = 12_000


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plots")
    x = gmwm.simulate(TRUTH, 2**14, seed=3, signals=2, freq=100)
    out = {
        "wv": gmwm.wv(x[:, 0], freq=100, name="gyro_x", robust=True, units="rad/s", adev=True),
        "allan": gmwm.allan(x[:, 0], freq=100, units="rad/s"),
        "fit": gmwm.fit(x[:, 0], "AR1+WN+RW", freq=100, units="rad/s", name="gyro_x"),
        "select": gmwm.select(x, "AR1+WN+RW", freq=100, names=["gyro_x", "gyro_y"], units="rad/s"),
        "gap": gmwm.gap(x[:, :1], freq=100, model="WN(sigma2=1e-5)+RW(gamma2=1e-11)", names=["gyro_x"],
                        replicates=40),
    }
    run(folder, "select", os.path.join(SOURCE, "data", "example_imu6.csv.gz"), "--model", "WN+RW", "--units",
        "gyro=rad/s,accel=m/s^2", "--json", "select.json", "--quiet")
    out["nav"] = gmwm.nav(str(folder / "select.json"), ["truth", "wnrw*2"], horizon=60.0, outages=[(20, 30)])
    manifest = write_fleet(folder, 4, TRUTH, 3, "WN(sigma2=4e-4)+RW(gamma2=1e-10)")
    out["fleet"] = gmwm.fleet(str(manifest), model="WN+RW", cache=None)
    return out


def rendered(ax, path):
    """The figure of `ax` as PNG bytes (written to `path`)."""
    fig = np.ravel(ax)[0].figure
    fig.savefig(path, dpi=80)
    plt.close(fig)
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE) and len(data) > MIN_PNG_BYTES, f"{path.name}: {len(data)} bytes"
    return data


def colours(ax):
    """The colours of the axes' lines that carry a legend label, one per label."""
    return {line.get_label(): matplotlib.colors.to_hex(line.get_color()) for line in ax.get_lines()
            if not line.get_label().startswith("_")}


def test_the_wv_plot_labels_its_unit_and_shows_the_classical_wv_beside_the_robust(results, tmp_path):
    ax = results["wv"].plot()
    assert ax.get_xlabel() == "tau [s]" and ax.get_ylabel() == "wavelet variance [(rad/s)^2]"
    assert set(colours(ax)) == {"huber WV", "classical WV"} and len(set(colours(ax).values())) == 2
    rendered(ax, tmp_path / "wv.png")


def test_the_allan_plot_draws_the_data_and_the_n_k_b_q_r_lines_in_their_unit(results, tmp_path):
    ax = results["allan"].plot()
    assert ax.get_xlabel() == "tau [s]" and ax.get_ylabel() == "Allan deviation [rad/s]"
    lines = colours(ax)
    assert "data" in lines and any(k.startswith("N / sqrt(tau)") for k in lines)
    assert any(k.startswith("K sqrt(tau / 3)") for k in lines) and any(k.startswith("0.664 B") for k in lines)
    # Q and R: only bounded on this gyroscope, and labelled so, in their units.
    assert any(k.startswith("sqrt(3) Q / tau, Q < ") and k.endswith(" rad") for k in lines), list(lines)
    assert any(k.startswith("R tau / sqrt(2), R < ") and k.endswith(" rad/s^2") for k in lines), list(lines)
    assert len(set(lines.values())) == len(lines)
    rendered(ax, tmp_path / "allan.png")


def test_the_fit_plot_decomposes_the_model_into_its_processes_which_sum_to_it(results, tmp_path):
    f = results["fit"]
    ax = f.plot()
    lines = colours(ax)
    assert ["AR1", "WN", "RW"] == [k for k in lines if k in ("AR1", "WN", "RW")]
    assert len(set(lines.values())) == len(lines), lines
    assert ax.get_ylabel() == "wavelet variance [(rad/s)^2]"
    labels, parts = gmwm._gmwm.model_wv(f.model, f.levels.tau, freq=f.freq)
    np.testing.assert_allclose(parts.sum(axis=0), f.implied_wv, rtol=1e-12)
    assert len(colours(f.plot(decomposition=False))) == 2  # the data and the model
    rendered(ax, tmp_path / "fit.png")


def test_the_selection_plot_ranks_the_models_beside_the_chosen_fit(results, tmp_path):
    column = results["select"][0]
    ranking_ax, fit_ax = column.plot()
    names = [t.get_text() for t in ranking_ax.get_yticklabels()]
    assert column.best in names and len(names) == min(len(column.ranking), 12)
    assert ranking_ax.get_xlabel().startswith("WVIC above the best")
    assert set(colours(ranking_ax)) == {"candidate", "chosen"}
    assert fit_ax.get_title() == f"gyro_x: chosen {column.best}"
    grid = results["select"].plot()
    assert grid.shape == (2, 2)
    rendered(fit_ax, tmp_path / "select.png")
    rendered(grid, tmp_path / "select_all.png")


def test_the_gap_plot_shows_each_level_against_the_reference_band(results, tmp_path):
    axes = results["gap"].plot()
    assert len(axes) == 1
    ax = axes[0]
    assert ax.get_ylabel() == "wavelet variance [(data unit)^2]" and ax.get_xlabel() == "tau [s]"
    lines = colours(ax)
    assert {"baseline's WV", "data, inside the band", "data, outside the band"} <= set(lines)
    assert len(set(lines.values())) == len(lines)
    rendered(ax, tmp_path / "gap.png")


def test_the_nav_plot_has_a_colour_per_filter_and_its_unit(results, tmp_path):
    n = results["nav"]
    ax = n.plot()
    assert ax.get_ylabel() == f"position error [{n.units['position']}]"
    lines = colours(ax)
    for f in n.filters:
        assert lines[f"{f.label}: RMS error"] == lines[f"{f.label}: claimed 3 sigma"]
    assert len({lines[f"{f.label}: RMS error"] for f in n.filters}) == len(n.filters)
    with pytest.raises(ValueError, match="quantity: found 'speed', expected position, velocity or attitude"):
        n.plot(quantity="speed")
    rendered(ax, tmp_path / "nav.png")


def test_the_fleet_plot_gives_each_unit_a_colour_and_boxes_the_flagged(results, tmp_path):
    r = results["fleet"]
    ax = r.plot(figure="N")
    assert [t.get_text() for t in ax.get_xticklabels()] == ["gyro_x", "gyro_y"]
    assert ax.get_ylabel().startswith("N [") and "sqrt(Hz)" in ax.get_ylabel()
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {"SN1", "SN2", "SN3", "SN4"} <= set(legend)
    assert ("flagged" in legend) == any(row.flags for row in r.rows)
    rendered(ax, tmp_path / "fleet.png")


def test_without_matplotlib_plot_says_how_to_install_it(results, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match="needs matplotlib: apt install python3-matplotlib"):
        results["fit"].plot()
