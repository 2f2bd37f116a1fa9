"""starter.plotting: pictures of the documented shapes with EGL and with the matplotlib fallback,
no-ops under DEFORMLAB_NO_PLOTS, shown once as PNG in a notebook."""

import io
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from starter import plotting, shapes
from starter.meshes import load_handles, load_mesh

REPO = Path(plotting.__file__).resolve().parent.parent
MAGENTA, RED = (255, 0, 255), (255, 0, 0)


@pytest.fixture(autouse=True)
def plots_on(monkeypatch):
    # tests/conftest.py turns pictures off for everyone else.
    monkeypatch.delenv("DEFORMLAB_NO_PLOTS", raising=False)
    monkeypatch.delenv("DEFORMLAB_PLOT_BACKEND", raising=False)


@pytest.fixture(params=["egl", "matplotlib"])
def backend_3d(request, monkeypatch):
    if request.param == "egl" and not plotting.opengl_available():
        pytest.skip(f"pyvista cannot render here: {plotting._opengl_reason}")
    if request.param == "matplotlib":
        monkeypatch.setenv("DEFORMLAB_PLOT_BACKEND", "matplotlib")
    return request.param


def count(img, rgb):
    return int(np.all(np.asarray(img) == rgb, axis=-1).sum())


def assert_picture(img, shape):
    assert isinstance(img, plotting.Picture) and isinstance(img, np.ndarray)
    assert img.shape == shape and img.dtype == np.uint8
    assert np.asarray(img).std() > 0, "blank picture"


def test_3d_pictures_have_the_documented_shapes(backend_3d):
    V, F = load_mesh("bar_coarse")
    handles = load_handles("bar_coarse")
    U = V.copy()
    U[:, 2] += 0.2 * (V[:, 0] - 2.0) ** 2
    W = np.column_stack([1 - V[:, 0] / 4, V[:, 0] / 4, V[:, 1], V[:, 2], 1.2 - V[:, 0] / 2])
    with warnings.catch_warnings():
        # The fallback warns; with EGL working it must not be taken.
        warnings.simplefilter("error", RuntimeWarning)
        assert_picture(plotting.show_mesh(V, F, scalars=V[:, 0], handles=handles["left"], title="bar"), (400, 400, 3))
        assert_picture(plotting.show_mesh(V, F, scalars=np.arange(len(F), dtype=float)), (400, 400, 3))
        assert_picture(plotting.show_deformation(V, U, F, handles=[handles["left"], handles["right"]]), (400, 800, 3))
        assert_picture(plotting.show_meshes([(V, F), (U, F, U[:, 2]), shapes.torus(n_major=12, n_minor=6)], titles="abc"), (400, 1200, 3))
        assert_picture(plotting.show_weights(V, F, W, handles=[handles["left"], handles["right"]], columns=[0, 1]), (400, 800, 3))
        assert_picture(plotting.show_weights(V, F, W), (800, 1600, 3))
    if backend_3d == "egl":
        assert plotting._plotter is not None, "pyvista was not used"


def test_2d_pictures_have_the_documented_shapes():
    V, F = load_mesh("character")
    handles = load_handles("character")
    W = np.column_stack([np.exp(-np.linalg.norm(V - V[i], axis=1) ** 2) for i in handles["points"]])
    assert_picture(plotting.show_mesh(V, F, handles=handles["points"]), (400, 400, 3))
    assert_picture(plotting.show_mesh(V, F, scalars=V[:, 1], title="height"), (400, 400, 3))
    assert_picture(plotting.show_deformation(V, V * [1.2, 0.8], F, handles=handles["bones"]), (400, 800, 3))
    assert_picture(plotting.show_meshes([(V, F), (V * 2, F, V[:, 0])]), (400, 800, 3))
    assert_picture(plotting.show_weights(V, F, W, handles=[np.array([i]) for i in handles["points"]]), (800, 1600, 3))
    assert_picture(plotting.show_weights(V, F, W[:, 0]), (400, 400, 3))


def test_point_and_energy_pictures_have_the_documented_shapes():
    rng = np.random.default_rng(1)
    for d in (2, 3):
        P = rng.normal(size=(25, d))
        Q = P @ np.linalg.qr(rng.normal(size=(d, d)))[0] + 1.0
        assert_picture(plotting.show_points(P, Q, title="before"), (400, 400, 3))
        assert_picture(plotting.show_points(P, Q, Q, title="aligned"), (400, 800, 3))
    assert_picture(plotting.show_energy(np.geomspace(5.0, 0.1, 12)), (400, 400, 3))
    assert_picture(plotting.show_energy({"arap": [3.0, 2.0, 1.5], "exact": [1.0, 0.0, 0.0]}, title="E"), (400, 400, 3))


def test_weights_out_of_unit_interval_get_the_out_of_range_colours_but_round_off_does_not():
    V, F = load_mesh("character")
    w = np.clip(1.5 - V[:, 1], 0.0, 1.0)
    exact = plotting.show_weights(V, F, w)
    round_off = plotting.show_weights(V, F, w + np.where(w == 0.0, -1e-9, 0.0) + np.where(w == 1.0, 1e-9, 0.0))
    # Round-off is drawn and printed as 0 and 1: the pictures are the same.
    assert np.array_equal(np.asarray(exact), np.asarray(round_off))
    outside = plotting.show_weights(V, F, 1.6 - V[:, 1])
    assert count(outside, MAGENTA) > count(exact, MAGENTA) + 500
    assert count(outside, RED) > count(exact, RED) + 500


def test_no_plots_returns_none_without_loading_plot_libraries():
    code = """
import sys
import numpy as np
from starter import plotting, shapes
V, F = shapes.bar(nx=2, ny=2, nz=2)
W = np.ones((len(V), 2)) / 2
results = [
    plotting.show_mesh(V, F), plotting.show_deformation(V, V, F), plotting.show_meshes([(V, F)]),
    plotting.show_weights(V, F, W), plotting.show_points(V, V, V), plotting.show_energy([1.0, 0.5]),
]
assert results == [None] * 6, results
loaded = [m for m in ("matplotlib", "pyvista", "vtk", "PIL") if m in sys.modules]
assert not loaded, loaded
print("ok")
"""
    env = {**os.environ, "DEFORMLAB_NO_PLOTS": "1"}
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=REPO, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr


def test_import_starter_exports_the_api_without_plot_libraries():
    code = """
import sys
import starter
assert [m for m in ("matplotlib", "pyvista", "vtk", "igl", "IPython") if m in sys.modules] == []
assert sorted(starter.__all__) == ["load_handles", "load_mesh", "mesh_names", "plotting", "shapes", "validation"]
V, F = starter.load_mesh("torus")
assert callable(starter.plotting.show_mesh) and callable(starter.shapes.bar) and callable(starter.validation.as_faces)
print(len(V), len(F))
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert run.returncode == 0 and run.stdout.split() == ["1152", "2304"], run.stderr


def test_crashing_opengl_falls_back_to_matplotlib_warning_once(monkeypatch):
    monkeypatch.setattr(plotting, "_PROBE", "raise RuntimeError('no EGL device')")
    monkeypatch.setattr(plotting, "_opengl", None)
    monkeypatch.setattr(plotting, "_warned", False)
    monkeypatch.setattr(plotting, "_plotter", None)
    assert plotting.opengl_available() is False
    V, F = shapes.torus(n_major=12, n_minor=6)
    with pytest.warns(RuntimeWarning, match="matplotlib.*no EGL device"):
        first = plotting.show_mesh(V, F)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        second = plotting.show_mesh(V, F)
    assert_picture(first, (400, 400, 3))
    assert np.array_equal(first, second)
    assert plotting._plotter is None


def test_unknown_backend_setting_raises_value_error(monkeypatch):
    monkeypatch.setenv("DEFORMLAB_PLOT_BACKEND", "opengl")
    V, F = shapes.bar(nx=2, ny=2, nz=2)
    with pytest.raises(ValueError, match="DEFORMLAB_PLOT_BACKEND"):
        plotting.show_mesh(V, F)


def _panels(monkeypatch):
    """The panels the next picture is drawn from (what its titles and colour bars say)."""
    seen = []
    monkeypatch.setattr(plotting, "_render", lambda panels, link_views=True: seen.extend(panels) or np.ones((4, 4, 3), np.uint8))
    return seen


def test_weight_panels_name_method_and_handle_and_label_their_colour_bar(monkeypatch):
    V, F = shapes.grid_2d(4, 4)
    panels = _panels(monkeypatch)
    W = np.column_stack([V[:, 0], 1 - V[:, 0] - 7.65e-20])
    plotting.show_weights(V, F, W, titles=["BBW: left foot", "BBW: right foot"])
    assert [p.title.split(":")[:2] for p in panels] == [["BBW", " left foot"], ["BBW", " right foot"]]
    assert all(p.label == "weight" for p in panels)
    assert "e-20" not in panels[1].title, "round-off below 0 is printed as 0"


def test_mesh_panels_carry_colour_bar_labels_shared_ranges_categories_and_a_view(monkeypatch, backend_3d):
    V, F = load_mesh("bar_coarse")
    flipped = (np.arange(len(F)) % 2).astype(float)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        img = plotting.show_meshes([(V, F, flipped), (V, F, flipped)], label="triangle", categories=("kept", "flipped"),
                                   view=(0.0, 0.0, 1.0))
        assert_picture(img, (400, 800, 3))
        # two flat colours, no blend between them: the bar is not a continuous range
        assert_picture(plotting.show_meshes([(V, F, V[:, 0] - 2.0)], label="x", clim=(-3.0, 3.0)), (400, 400, 3))
    panels = _panels(monkeypatch)
    plotting.show_meshes([(V, F, V[:, 0]), (V, F, V[:, 1] - 7.65e-20 - V[:, 1].min())], label=["x", "volume change"])
    assert [p.label for p in panels] == ["x", "volume change"]
    assert plotting._clim(panels[1])[0] == 0.0, "a colour range starting within round-off of 0 starts at 0"
    assert plotting._colormap(plotting._Panel(V, F, categories=("kept", "flipped"))).N == 2


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda V, F: plotting.show_mesh(V, F, scalars=np.ones(7)), "scalars"),
        (lambda V, F: plotting.show_mesh(V, F, handles=[0, len(V)]), "handles"),
        (lambda V, F: plotting.show_mesh(V, F[:, :2]), "F"),
        (lambda V, F: plotting.show_deformation(V, V[:-1], F), "U"),
        (lambda V, F: plotting.show_deformation(V, V, F, titles=("one",)), "titles"),
        (lambda V, F: plotting.show_meshes([]), "meshes"),
        (lambda V, F: plotting.show_meshes([(V, F)], titles=["a", "b"]), "titles"),
        (lambda V, F: plotting.show_meshes([(V, F, np.ones(3))]), r"meshes\[0\]\[2\]"),
        (lambda V, F: plotting.show_meshes([(V, F)], label=["a", "b"]), "label"),
        (lambda V, F: plotting.show_meshes([(V, F, np.ones(len(V)))], clim=(1.0, 0.0)), "clim"),
        (lambda V, F: plotting.show_meshes([(V, F, np.full(len(F), 2.0))], categories=("kept", "flipped")), r"meshes\[0\]\[2\]"),
        (lambda V, F: plotting.show_meshes([(V, F)], view=(0.0, 0.0, 0.0)), "view"),
        (lambda V, F: plotting.show_weights(V, F, np.ones((len(V), 2)), titles=["only one"]), "titles"),
        (lambda V, F: plotting.show_weights(V, F, np.ones((3, 2))), "W"),
        (lambda V, F: plotting.show_weights(V, F, np.ones((len(V), 2)), columns=[2]), "columns"),
        (lambda V, F: plotting.show_weights(V, F, np.ones((len(V), 2)), handles=[[0], [-1]]), r"handles\[1\]"),
        (lambda V, F: plotting.show_points(V, V[:-1]), "Q"),
        (lambda V, F: plotting.show_points(V, V, V[:, :1]), "P_aligned"),
        (lambda V, F: plotting.show_energy([]), "energies"),
        (lambda V, F: plotting.show_energy({"arap": [1.0, np.nan]}), "energies\\['arap'\\]"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(call, name):
    V, F = shapes.grid_2d(3, 3)
    with pytest.raises(ValueError, match=name):
        call(V, F)


def test_picture_png_decodes_to_the_same_pixels():
    from PIL import Image

    img = plotting.show_energy([3.0, 2.0, 1.0])
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(img._repr_png_())).convert("RGB")), img)


@pytest.mark.slow
def test_notebook_shows_each_picture_once_as_an_embedded_png(tmp_path):
    import nbformat
    from nbclient import NotebookClient

    cells = [
        "from starter import plotting, shapes\nV, F = shapes.grid_2d(4, 4)",
        "plotting.show_mesh(V, F)",
        "img = plotting.show_mesh(V, F, scalars=V[:, 0])\nimg.shape",
        "img",
    ]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    NotebookClient(nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()

    def pngs(cell):
        return [o for o in cell.outputs if "image/png" in o.get("data", {})]

    setup, last_expression, assigned, later = nb.cells
    assert pngs(setup) == []
    assert len(pngs(last_expression)) == 1 and [o.output_type for o in last_expression.outputs] == ["display_data"]
    assert len(pngs(assigned)) == 1
    assert [o["data"]["text/plain"] for o in assigned.outputs if o.output_type == "execute_result"] == ["(400, 400, 3)"]
    assert len(pngs(later)) == 1
