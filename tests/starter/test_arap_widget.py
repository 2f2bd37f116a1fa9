"""starter.arap_widget: the warm-started ARAP frames, their energy, the budget of iterations, the mouse,
the frame thread, the pictures (EGL and the matplotlib fallback) and the GIF/MP4 export."""

import io

import igl
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from reference.arap import arap_energy, arap_rotations, cotangent_weights
from reference.sign_correction import optimal_rotation
from starter import plotting
from starter.arap_widget import ArapRenderer, ArapWidget, _largest_rotation_traces
from starter.meshes import load_handles, load_mesh

SIZE = (320, 200)


@pytest.fixture(scope="module")
def bar():
    V, F = load_mesh("bar")
    ends = load_handles("bar")
    return V, F, [ends["left"], ends["right"]]


@pytest.fixture(params=["egl", "matplotlib"])
def backend(request, monkeypatch):
    if request.param == "egl" and not plotting.opengl_available():
        pytest.skip(f"pyvista cannot render here: {plotting._opengl_reason}")
    monkeypatch.setenv("DEFORMLAB_PLOT_BACKEND", "pyvista" if request.param == "egl" else "matplotlib")
    return "pyvista" if request.param == "egl" else "matplotlib"


@pytest.fixture
def widget(bar, backend):
    V, F, handles = bar
    w = ArapWidget(V, F, handles, names=["left", "right"], size=SIZE, live=False)
    yield w
    w.close()


def picture(w):
    return np.asarray(Image.open(io.BytesIO(w.image.value)).convert("RGB"))


def reference_energy(V, F, U):
    C = cotangent_weights(V, F)
    return arap_energy(V, U, F, C, arap_rotations(V, U, F, C))


def test_the_rest_shape_has_zero_energy_and_stays_put(widget, bar):
    V, F, _ = bar
    record = widget.step()
    # igl.arap_solve fits 3D rotations in single precision
    np.testing.assert_allclose(widget.U, V, atol=1e-6)
    assert record["energy"] == pytest.approx(0.0, abs=1e-10) and not record["moved"]


def test_each_frame_warm_starts_igl_arap_solve_from_the_previous_frame(widget, bar):
    V, F, handles = bar
    widget.move_handle(1, [0.0, 0.5, 0.3])
    frames = [widget.step() for _ in range(3)]
    # the same iterations, one call from the rest pose: frames chain their starts
    data = igl.ARAPData()
    data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
    data.max_iter = sum(f["iterations"] for f in frames)
    b = np.concatenate(handles)
    igl.arap_precomputation(V, F, 3, b.astype(np.int32), data)
    np.testing.assert_allclose(widget.U, igl.arap_solve(widget.targets(), data, V.copy()), atol=1e-9)
    assert [f["moved"] for f in frames] == [True, False, False]
    np.testing.assert_allclose(widget.U[handles[1]], V[handles[1]] + [0.0, 0.5, 0.3], atol=1e-12)
    np.testing.assert_allclose(widget.U[handles[0]], V[handles[0]], atol=1e-12)


def test_the_energy_shown_is_stage_03s_energy_with_the_best_rotations(widget, bar):
    V, F, _ = bar
    widget.move_handle(1, [0.0, 0.8, 0.6])
    widget.step()
    assert widget.energy == pytest.approx(reference_energy(V, F, widget.U), rel=1e-9)
    assert f"ARAP energy {widget.energy:.9g}" in widget.label.value


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(1e-6, 1e6))
def test_the_largest_rotation_trace_is_that_of_the_optimal_rotation(seed, scale):
    S = scale * np.random.default_rng(seed).normal(size=(50, 3, 3))
    expected = np.einsum("nab,nba->n", optimal_rotation(S), S)
    np.testing.assert_allclose(_largest_rotation_traces(S), expected, rtol=1e-12, atol=1e-12 * scale)


def test_the_largest_rotation_trace_of_flat_and_zero_cells():
    flat = np.diag([2.0, 1.0, 0.0])
    turned = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]) @ flat
    np.testing.assert_allclose(_largest_rotation_traces(np.stack([flat, turned, np.zeros((3, 3))])), [3.0, 3.0, 0.0],
                               atol=1e-12)


def test_at_still_handles_the_energy_never_rises_and_the_frames_settle(widget, bar):
    V, F, _ = bar
    widget.move_handle(1, [0.0, 1.0, 1.0])
    widget.move_handle(0, [0.0, 0.0, -0.3])
    widget.settle_iterations = 10_000
    frames = widget.settle(max_frames=300)
    energies = [f["energy"] for f in widget.frames]
    assert frames < 300, "the energy never settled"
    assert np.all(np.diff(energies) <= 1e-12 * energies[0]), np.diff(energies).max()
    # settled means a frame's decrease fell below settle_tol of the energy
    assert energies[-2] - energies[-1] <= widget.settle_tol * energies[-1]
    assert widget.energy == pytest.approx(reference_energy(V, F, widget.U), rel=1e-9)


def test_frames_at_still_handles_stop_after_settle_iterations(widget):
    widget.settle_tol = 0.0  # never settled by the energy alone
    widget.target_fps = 1e6  # a budget of one iteration
    widget.settle_after = 0.0
    widget.max_iterations = 4
    widget.settle_iterations = 10
    widget.move_handle(1, [0.0, 1.0, 1.0])
    widget.step()
    frames = widget.settle(max_frames=50)
    assert [f["iterations"] for f in list(widget.frames)[-frames:]] == [1, 2, 4, 4]  # 11 iterations >= 10


def test_the_iteration_budget_fills_the_frame_rate_target_while_the_handles_move(widget):
    widget.move_handle(1, [0.0, 0.3, 0.0])
    widget.step()
    assert widget.frames[-1]["iterations"] == 1  # nothing measured yet
    # a frame rate target far below what the machine does: the budget grows to the cap
    widget.target_fps = 1e-3
    widget.move_handle(1, [0.0, 0.4, 0.0])
    widget.step()
    assert widget.frames[-1]["iterations"] == widget.max_iterations
    # one far above it: still one iteration a frame, never none
    widget.target_fps = 1e6
    widget.move_handle(1, [0.0, 0.5, 0.0])
    widget.step()
    assert widget.frames[-1]["iterations"] == 1
    # in between: the iterations that fit in the measured frame
    frames = list(widget.frames)
    iteration = np.mean([f["solve_s"] / f["iterations"] for f in frames])
    rest = np.mean([f["total_s"] - f["solve_s"] for f in frames])
    widget.target_fps = 1.0 / (rest + 5.5 * iteration)
    assert widget._budget() == 5


def test_once_the_drag_has_ended_each_frame_doubles_the_iterations_up_to_the_cap(widget):
    widget.target_fps = 1e6  # a budget of one iteration
    widget.max_iterations = 6
    widget.settle_after = 3600.0  # a drag paused between two mouse events: the frame rate still counts
    widget.move_handle(1, [0.0, 0.5, 0.5])
    assert [widget.step()["iterations"] for _ in range(4)] == [1, 1, 1, 1]
    widget.settle_after = 0.0  # the drag has ended
    assert [widget.step()["iterations"] for _ in range(5)] == [1, 2, 4, 6, 6]
    widget.move_handle(1, [0.0, 0.6, 0.5])
    assert widget.step()["iterations"] == 1


def test_dragging_a_handle_moves_it_in_the_view_plane_with_the_mouse(widget, bar):
    V, F, handles = bar
    start = widget.handle_pixels()[1].mean(axis=0)
    assert widget.press(*start) == 1
    widget.drag(*(start + [30.0, -20.0]))
    widget.step()
    assert widget.label.value.endswith("· dragging the right")
    widget.release()
    shift = widget.offsets[1]
    assert abs(shift @ widget.renderer.view) < 1e-12  # in the view plane
    widget.step()
    np.testing.assert_allclose(widget.handle_pixels()[1].mean(axis=0), start + [30.0, -20.0], atol=1e-9)
    np.testing.assert_array_equal(widget.offsets[0], 0.0)


def test_a_press_away_from_every_handle_grabs_nothing(widget):
    assert widget.press(1.0, 1.0) is None
    widget.drag(100.0, 100.0)
    np.testing.assert_array_equal(widget.offsets, 0.0)


def test_browser_mouse_events_drive_press_drag_and_release(widget):
    x, y = widget.handle_pixels()[1].mean(axis=0)
    box = {"boundingRectWidth": SIZE[0] * 2, "boundingRectHeight": SIZE[1] * 2}  # the page shows it at twice the size
    widget._mouse_event({"type": "mousedown", "relativeX": 2 * x, "relativeY": 2 * y, **box})
    widget._mouse_event({"type": "mousemove", "relativeX": 2 * x + 20, "relativeY": 2 * y, **box})
    widget._mouse_event({"type": "mouseup", "relativeX": 2 * x + 40, "relativeY": 2 * y, **box})
    np.testing.assert_allclose(widget.offsets[1], widget.renderer.to_offset([20.0, 0.0]), atol=1e-12)
    widget._mouse_event({"type": "mousemove", "relativeX": 0, "relativeY": 0, **box})
    np.testing.assert_allclose(widget.offsets[1], widget.renderer.to_offset([20.0, 0.0]), atol=1e-12)


def test_the_frame_thread_follows_moves_and_settles(bar):
    V, F, handles = bar
    w = ArapWidget(V, F, handles, size=SIZE)
    try:
        w.move_handle(1, [0.0, 0.4, 0.2])
        assert w.wait_until_settled(timeout=120)
        np.testing.assert_allclose(w.U[handles[1]], V[handles[1]] + [0.0, 0.4, 0.2], atol=1e-12)
        assert w.energy == pytest.approx(reference_energy(V, F, w.U), rel=1e-9)
        assert w.label.value.startswith(f"frame {w.frames[-1]['frame']} (handles still)")
    finally:
        w.close()
    assert not w._thread.is_alive()


def test_the_picture_shows_the_moved_handle_where_it_went(widget, bar, backend):
    V, F, handles = bar
    before = picture(widget)
    widget.move_handle(1, widget.renderer.to_offset([0.0, -40.0]))
    widget.step()
    after = picture(widget)

    def blue_centre(img):
        """Centre of the blue (the right end's) pixels; shading darkens them, so compare channels."""
        r, g, b = np.moveaxis(img.astype(int), -1, 0)
        rows, cols = np.nonzero((b > r + 60) & (b > g + 25))
        assert len(rows) > 20, "the right end is not in the picture"
        return np.array([cols.mean(), rows.mean()])

    assert before.shape == after.shape == (SIZE[1], SIZE[0], 3)
    np.testing.assert_allclose(blue_centre(after) - blue_centre(before), [0.0, -40.0], atol=4.0)
    assert widget.renderer.backend == backend


def test_pixels_and_offsets_agree_with_the_view(bar):
    V, F, handles = bar
    r = ArapRenderer(V, F, handles, size=(400, 300))
    np.testing.assert_allclose(r.to_pixels(r.centre[None]), [[200.0, 150.0]])
    P = V[:5]
    np.testing.assert_allclose(r.to_pixels(P + r.to_offset([12.0, -7.0])), r.to_pixels(P) + [12.0, -7.0], atol=1e-9)


def test_export_animation_writes_one_gif_frame_per_step_and_leaves_the_widget(widget, tmp_path):
    offsets = np.zeros((4, 2, 3))
    offsets[:, 1, 2] = np.linspace(0.0, 0.6, 4)
    path = widget.export_animation(tmp_path / "bend.gif", offsets, fps=10, iterations=2)
    with Image.open(path) as gif:
        assert gif.n_frames == 4 and gif.info["duration"] == 100
    np.testing.assert_array_equal(widget.offsets, 0.0)
    np.testing.assert_array_equal(widget.U, widget.V)


def test_export_animation_writes_an_mp4(widget, tmp_path):
    av = pytest.importorskip("av")
    offsets = np.zeros((3, 2, 3))
    offsets[:, 1, 1] = [0.0, 0.2, 0.4]
    path = widget.export_animation(tmp_path / "bend.mp4", offsets, fps=10, iterations=1)
    with av.open(str(path)) as video:
        assert sum(1 for _ in video.decode(video=0)) == 3


@pytest.mark.parametrize("call, message", [
    (lambda w, p: w.move_handle(2, [0, 0, 0]), "j must be a handle index"),
    (lambda w, p: w.move_handle(0, [0, 0]), "offset must have shape"),
    (lambda w, p: w.export_animation(p / "a.png", np.zeros((1, 2, 3))), "path must end in .gif or .mp4"),
    (lambda w, p: w.export_animation(p / "a.gif", np.zeros((1, 3, 3))), "offsets must have shape"),
    (lambda w, p: w.export_animation(p / "a.gif", np.zeros((1, 2, 3)), fps=0), "fps must be positive"),
    (lambda w, p: w.export_animation(p / "a.gif", np.zeros((1, 2, 3)), iterations=0), "iterations must be a positive"),
    (lambda w, p: w.arap_energy(np.zeros((3, 3))), "U must have the shape of V"),
])
def test_bad_calls_are_refused_naming_the_argument(bar, tmp_path, call, message):
    V, F, handles = bar
    w = ArapWidget(V, F, handles, size=SIZE, live=False)
    try:
        with pytest.raises(ValueError, match=message):
            call(w, tmp_path)
    finally:
        w.close()


@pytest.mark.parametrize("change, message", [
    ({"handle_sets": []}, "handle_sets must be a non-empty sequence"),
    ({"handle_sets": [[0, 1], []]}, r"handle_sets\[1\] is empty"),
    ({"handle_sets": [[0, 1], [1, 2]]}, "handle_sets"),
    ({"names": ["one"]}, "names must have one entry per handle"),
    ({"target_fps": 0}, "target_fps must be positive"),
    ({"max_iterations": 0}, "max_iterations must be a positive integer"),
    ({"history": 0}, "history must be a positive integer"),
    ({"settle_after": -1}, "settle_after must be non-negative"),
    ({"settle_iterations": 0}, "settle_iterations must be a positive integer"),
    ({"view": (0, 0, 1), "up": (0, 0, 2)}, "must be non-zero and not parallel"),
])
def test_bad_widget_arguments_are_refused_naming_the_argument(bar, change, message):
    V, F, handles = bar
    kwargs = {"handle_sets": handles, "size": SIZE, "live": False} | change
    with pytest.raises(ValueError, match=message):
        ArapWidget(V, F, **kwargs)


def test_a_component_without_a_handle_is_refused():
    V, F = load_mesh("bar_coarse")
    two = np.vstack([V, V + [10.0, 0.0, 0.0]]), np.vstack([F, F + len(V)])
    with pytest.raises(ValueError, match="every connected component"):
        ArapWidget(*two, [[0]], size=SIZE, live=False)


@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5))
def test_any_drag_of_the_right_end_lowers_the_energy_frame_by_frame_once_still(bar, dy, dz):
    V, F, handles = bar
    w = ArapWidget(V, F, handles, size=(64, 64), live=False)
    try:
        w.move_handle(1, [0.0, dy, dz])
        energies = [w.step()["energy"] for _ in range(8)]
        # rounding is relative to the energy's terms, 3 Σ C ‖e‖² among them
        assert np.all(np.diff(energies) <= 1e-12 * (energies[0] + w._rest_term))
    finally:
        w.close()


def test_the_student_bundle_ships_the_arap_demo_and_its_widget_without_reference_code(tmp_path):
    import ast
    import zipfile
    from pathlib import Path

    import jupytext
    import nbformat

    from grader.build.release import scan_for_leaks, write_bundle
    from grader.paths import CoursePaths

    root = Path(__file__).resolve().parents[2]
    for name in ("notebooks", "starter", "data"):
        (tmp_path / name).symlink_to(root / name)
    paths = CoursePaths(tmp_path)
    (paths.release / "deformation").mkdir(parents=True)
    with zipfile.ZipFile(write_bundle(paths, "deformation")) as z:
        nb = nbformat.reads(z.read("deformation/demo_arap.ipynb").decode(), as_version=4)
        widget = z.read("deformation/starter/arap_widget.py").decode()
        assert "deformation/data/bar_fine.npz" in z.namelist()
    authored = jupytext.read(root / "notebooks" / "demo_arap" / "demo_arap.py")
    assert [(c.cell_type, c.source) for c in nb.cells] == [(c.cell_type, c.source) for c in authored.cells]
    assert all(not c.get("outputs") for c in nb.cells)
    imported = set()
    for source in [widget] + [c.source for c in nb.cells if c.cell_type == "code"]:
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom):
                imported.add(node.module.split(".")[0])
            elif isinstance(node, ast.Import):
                imported.update(a.name.split(".")[0] for a in node.names)
    assert not imported & {"reference", "grader"}, imported
    assert scan_for_leaks({"demo_arap.ipynb": nbformat.writes(nb), "starter/arap_widget.py": widget}) == []
