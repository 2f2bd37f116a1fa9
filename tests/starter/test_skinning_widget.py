"""starter.skinning_widget: normalized BBW weights, the slider widget driven programmatically, its
pictures (EGL and the matplotlib fallback) and the GIF export."""

import io
import re
import threading

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from PIL import Image

from starter import plotting
from starter.meshes import load_handles, load_mesh
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms
from starter.skinning_widget import SkinRenderer, SkinningWidget, skinning_weights

NAMES = ("spine", "left arm", "right arm", "left leg", "right leg")
SIZE = (320, 240)


@pytest.fixture(scope="module")
def character():
    V, F = load_mesh("character")
    bones = load_handles("character")["bones"]
    return V, F, bones, skinning_weights(V, F, bones)


@pytest.fixture(params=["egl", "matplotlib"])
def backend(request, monkeypatch):
    if request.param == "egl" and not plotting.opengl_available():
        pytest.skip(f"pyvista cannot render here: {plotting._opengl_reason}")
    monkeypatch.setenv("DEFORMLAB_PLOT_BACKEND", "pyvista" if request.param == "egl" else "matplotlib")
    return "pyvista" if request.param == "egl" else "matplotlib"


@pytest.fixture
def widget(character, backend):
    V, F, bones, W = character
    w = SkinningWidget(V, F, W, bones, CHARACTER_PARENTS, names=NAMES, size=SIZE)
    yield w
    w.renderer.close()


def skinned(V, W, T):
    """LBS straight from the formula, ``u_i = Σ_j W[i, j] T_j [v_i; 1]``."""
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :2], V) + W @ T[:, :, 2]


def picture(w):
    return np.asarray(Image.open(io.BytesIO(w.image.value)).convert("RGB"))


def foreground(img):
    return int(np.any(img != 255, axis=-1).sum())


def pixel(renderer, x):
    """Row and column of the point ``x`` in the renderer's fixed view."""
    col, row = np.rint(renderer.to_pixels([x])[0]).astype(int)
    return row, col


def test_weights_are_one_on_their_bone_bounded_and_a_partition_of_unity_on_the_fine_character():
    V, F = load_mesh("character_fine")
    bones = load_handles("character_fine")["bones"]
    assert len(V) > 10_000 and len(bones) == 5
    W = skinning_weights(V, F, bones)
    assert W.shape == (len(V), 5)
    assert W.min() >= 0.0 and W.max() <= 1.0
    assert np.abs(W.sum(axis=1) - 1.0).max() < 1e-12
    for j, bone in enumerate(bones):
        assert np.array_equal(W[bone], np.eye(5)[np.full(len(bone), j)])
    # Each bone's weight is largest on its own limb: the arm tips belong to the arms.
    assert np.argmax(W[load_handles("character_fine")["points"]], axis=1).tolist() == [0, 1, 2, 3, 4]


def test_the_rest_pose_reproduces_the_mesh(widget, character):
    V = character[0]
    assert np.array_equal(widget.T, np.tile(np.eye(2, 3), (5, 1, 1)))
    assert np.abs(widget.U - V).max() < 1e-12


def test_moving_one_slider_updates_the_transforms_and_the_mesh_to_the_exact_lbs_result(widget, character):
    V, _, bones, W = character
    before = widget.image.value
    widget.angle_sliders[1].value = 40
    T = bone_transforms(bone_joints(V, bones), np.radians([0.0, 40.0, 0.0, 0.0, 0.0]), CHARACTER_PARENTS)
    assert np.array_equal(widget.T, T)
    assert np.abs(widget.U - skinned(V, W, T)).max() < 1e-12
    assert widget.image.value != before
    # The left arm turned, so its tip moved; the right arm's did not.
    assert np.linalg.norm(widget.U[bones[1][-1]] - V[bones[1][-1]]) > 0.1
    assert np.abs(widget.U[bones[2]] - V[bones[2]]).max() < 1e-12


def test_the_translation_sliders_move_the_whole_mesh(widget, character):
    V = character[0]
    widget.translation_sliders[0].value = 25  # centimetres: hundredths of the mesh unit
    widget.translation_sliders[1].value = -10
    assert np.abs(widget.U - (V + [0.25, -0.1])).max() < 1e-12


# set_pose sets every slider, so the widget carried over between examples holds no state that matters.
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    angles=st.lists(st.floats(-np.pi, np.pi, allow_nan=False), min_size=5, max_size=5),
    translation=st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)),
)
def test_every_pose_set_through_the_sliders_gives_the_lbs_of_its_forward_kinematics(widget, character, angles, translation):
    V, _, bones, W = character
    widget.set_pose(angles, translation)
    # The sliders hold whole degrees and centimetres.
    assert [s.value for s in widget.angle_sliders] == np.rint(np.degrees(angles)).astype(int).tolist()
    assert [s.value for s in widget.translation_sliders] == np.rint(100 * np.array(translation)).astype(int).tolist()
    T = bone_transforms(bone_joints(V, bones), widget.angles, CHARACTER_PARENTS, widget.translation)
    assert np.abs(widget.U - skinned(V, W, T)).max() < 1e-12


def test_set_pose_clamps_to_the_slider_ranges(widget, character):
    V, _, bones, W = character
    widget.set_pose([4.0, -4.0, 0.0, 0.0, 0.0], [2.0, -2.0])
    assert [s.value for s in widget.angle_sliders[:2]] == [180, -180]
    assert [s.value for s in widget.translation_sliders] == [50, -50]
    T = bone_transforms(bone_joints(V, bones), np.radians([180, -180, 0, 0, 0]), CHARACTER_PARENTS, [0.5, -0.5])
    assert np.abs(widget.U - skinned(V, W, T)).max() < 1e-12


def test_set_pose_updates_once_and_the_picture_shows_that_pose(widget):
    changes = []
    widget.image.observe(lambda change: changes.append(change), names="value")
    widget.set_pose(np.radians([10.0, -30.0, 45.0, 5.0, -5.0]), [0.1, 0.05])
    assert len(changes) == 1
    img = picture(widget)
    assert img.shape == (SIZE[1], SIZE[0], 3)
    assert np.array_equal(img, widget.renderer.render(widget.U))
    assert 0.05 * img.shape[0] * img.shape[1] < foreground(img) < 0.6 * img.shape[0] * img.shape[1]


def test_the_picture_draws_each_posed_bone_where_lbs_put_it(widget, character):
    _, _, bones, _ = character
    widget.set_pose(np.radians([20.0, -60.0, 70.0, 15.0, -25.0]), [0.2, -0.1])
    img = picture(widget)
    for bone in bones:
        row, col = pixel(widget.renderer, (widget.U[bone[0]] + widget.U[bone[-1]]) / 2)
        patch = img[row - 2:row + 3, col - 2:col + 3].astype(int)
        assert (patch.max(axis=-1) < 90).any(), f"no dark bone pixel near ({row}, {col}) ({widget.renderer.backend})"


def test_the_label_reports_lbs_updates_and_rendered_frames_per_second_separately(widget):
    for k in range(5):
        widget.angle_sliders[0].value = 5 * k
    rates = widget.frame_rates()
    assert rates["lbs_updates_per_second"] > rates["rendered_frames_per_second"] > 0
    numbers = re.search(r"LBS: ([\d,]+) updates/s · rendered: ([\d.]+) frames/s \((\w+),", widget.label.value)
    assert numbers, widget.label.value
    assert float(numbers[1].replace(",", "")) == round(rates["lbs_updates_per_second"])
    assert float(numbers[2]) == round(rates["rendered_frames_per_second"], 1)
    assert numbers[3] == widget.renderer.backend


def test_export_animation_writes_one_gif_frame_per_pose_and_leaves_the_sliders(widget, tmp_path):
    k = 12
    phase = 2 * np.pi * np.arange(k) / k
    angles = np.column_stack([0.3 * np.sin(phase), -np.sin(phase), np.sin(phase), 0.4 * np.cos(phase), -0.4 * np.cos(phase)])
    translations = np.column_stack([0.1 * np.sin(phase), 0.05 * np.cos(phase)])
    sliders = [s.value for s in widget.angle_sliders + widget.translation_sliders]
    path = widget.export_animation(tmp_path / "wave.gif", angles, translations, fps=10)
    assert path == tmp_path / "wave.gif"
    with Image.open(path) as gif:
        assert gif.format == "GIF" and gif.n_frames == k and gif.size == SIZE
        assert gif.info["duration"] == 100 and gif.info["loop"] == 0
        gif.seek(3)
        assert foreground(np.asarray(gif.convert("RGB"))) > 0
    assert [s.value for s in widget.angle_sliders + widget.translation_sliders] == sliders


def test_export_animation_writes_an_mp4_whose_frames_are_the_widgets_pictures(widget, tmp_path):
    av = pytest.importorskip("av", reason="PyAV (the video extra) is not installed")
    angles = np.radians([[0, 0, 0, 0, 0], [10, -40, 40, 5, -5], [20, -80, 80, 10, -10]])
    path = widget.export_animation(tmp_path / "wave.mp4", angles, fps=12)
    assert path == tmp_path / "wave.mp4"
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        assert (stream.codec_context.name, stream.width, stream.height, stream.average_rate) == ("h264", *SIZE, 12)
        decoded = [frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)]
    assert len(decoded) == 3
    for pose, picture in zip(angles, decoded):
        drawn = widget.renderer.render(widget._positions(pose, np.zeros(2))[1]).astype(float)
        mse = np.mean((picture - drawn) ** 2)
        assert 10 * np.log10(255**2 / mse) >= 30, "each decoded frame is the picture of its pose"
    assert np.degrees(widget.angles).tolist() == [0.0] * 5  # the sliders stay where they were


def test_a_slider_change_delivered_on_another_thread_renders_the_same_picture(widget):
    # A kernel may run comm handlers (slider changes) on another thread than cell execution.
    widget.set_pose(np.radians([10.0, -30.0, 45.0, 5.0, -5.0]))
    expected = widget.renderer.render(widget.U)
    done = []
    worker = threading.Thread(target=lambda: done.append(widget.renderer.render(widget.U)))
    worker.start()
    worker.join()
    assert np.array_equal(done[0], expected)


def test_the_renderer_uses_the_backend_that_works(widget, backend):
    assert widget.renderer.backend == backend
    assert "(" + backend + "," in widget.label.value


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda w, tmp: w.export_animation(tmp / "a.avi", np.zeros((2, 5))), "path must end in .gif or .mp4"),
        (lambda w, tmp: w.export_animation(tmp / "a.gif", np.zeros((2, 4))), "angles must have shape (k, 5)"),
        (lambda w, tmp: w.export_animation(tmp / "a.gif", np.zeros((0, 5))), "angles must have shape (k, 5)"),
        (lambda w, tmp: w.export_animation(tmp / "a.gif", np.zeros((2, 5)), np.zeros((3, 2))), "translations must have shape (2, 2)"),
        (lambda w, tmp: w.export_animation(tmp / "a.gif", np.zeros((2, 5)), fps=0), "fps must be positive"),
        (lambda w, tmp: w.export_animation(tmp / "a.mp4", np.zeros((2, 5)), fps=float("inf")), "fps contains NaN or inf"),
        (lambda w, tmp: w.set_pose(np.zeros(4)), "angles must have one entry per bone (5)"),
        (lambda w, tmp: w.set_pose(np.zeros(5), [np.nan, 0.0]), "translation contains NaN"),
        (lambda w, tmp: w.renderer.render(np.zeros((3, 2))), "U must have the shape of V"),
        (lambda w, tmp: w.renderer.to_pixels(np.zeros((3, 3))), "P must have shape (k, 2)"),
        (lambda w, tmp: w.renderer.to_world(np.zeros(2)), "pixels must be a 2-D array"),
    ],
)
def test_bad_calls_are_refused_naming_the_argument(widget, tmp_path, call, message):
    with pytest.raises(ValueError) as info:
        call(widget, tmp_path)
    assert message in str(info.value)


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(W=np.ones((10, 5))), "W must have shape (1547, 5)"),
        (dict(names=("a", "b")), "names must have one entry per bone (5)"),
        (dict(parents=(-1, 0, 1, 2, 2, 0)), "parents must have one entry per bone (5)"),
        (dict(parents=(1, 0, -1, -1, -1)), "parents has a cycle"),
        (dict(max_translation=0.001), "max_translation must be at least 0.01"),
        (dict(history=0), "history must be a positive integer"),
        (dict(size=(8, 8)), "size must be (width, height) with both at least 16 pixels"),
    ],
)
def test_bad_widget_arguments_are_refused_naming_the_argument(character, change, message):
    V, F, bones, W = character
    args = dict(V=V, F=F, W=W, bones=bones, parents=CHARACTER_PARENTS) | change
    with pytest.raises(ValueError) as info:
        SkinningWidget(**args)
    assert message in str(info.value)


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(handle_sets=[]), "handle_sets must be a non-empty sequence"),
        (dict(handle_sets=[np.array([0, 1]), np.array([], dtype=np.int64)]), "handle_sets[1] is empty"),
        (dict(handle_sets=[np.array([0, 1]), np.array([1, 2])]), "has duplicate vertex 1"),
        (dict(handle_sets=[np.array([0, 10**6])]), "out of range"),
    ],
)
def test_bad_weight_arguments_are_refused_naming_the_argument(character, change, message):
    V, F, bones, _ = character
    with pytest.raises(ValueError) as info:
        skinning_weights(**(dict(V=V, F=F, handle_sets=bones) | change))
    assert message in str(info.value)


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(W=np.ones((3, 5))), "W must have one row per vertex (1547)"),
        (dict(reach=0.0), "reach must be positive"),
        (dict(reach=np.inf), "reach contains NaN or inf"),
        (dict(bones=[np.array([0, 10**6])]), "bones[0] ends at vertex 1000000, out of range"),
        (dict(V=np.zeros((1547, 3))), "V must have 2 columns"),
    ],
)
def test_bad_renderer_arguments_are_refused_naming_the_argument(character, change, message):
    V, F, _, W = character
    with pytest.raises(ValueError) as info:
        SkinRenderer(**(dict(V=V, F=F, W=W) | change))
    assert message in str(info.value)


def test_a_renderer_without_bones_draws_only_the_mesh(character, backend):
    V, F, _, W = character
    renderer = SkinRenderer(V, F, W, size=(64, 64))
    try:
        img = renderer.render(V)
        assert img.shape == (64, 64, 3) and img.dtype == np.uint8
        assert foreground(img) > 0 and not (img.max(axis=-1) < 60).any()
    finally:
        renderer.close()


def _turn(a, b):
    """Signed angle from vector a to vector b, in degrees."""
    return np.degrees(np.arctan2(a[0] * b[1] - a[1] * b[0], a @ b))


def test_pixels_and_mesh_units_map_back_and_forth_with_the_view_centre_in_the_middle(widget):
    r = widget.renderer
    assert np.allclose(r.to_pixels([r.centre]), [[SIZE[0] / 2, SIZE[1] / 2]])
    # one reach above the centre is the top edge; y grows downwards in pixels
    assert np.allclose(r.to_pixels([r.centre + [0.0, r.reach]]), [[SIZE[0] / 2, 0.0]])
    points = np.random.default_rng(1).uniform(-2, 2, (50, 2))
    assert np.allclose(r.to_world(r.to_pixels(points)), points, atol=1e-12)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(bone=st.integers(0, 4), dx=st.floats(-80, 80), dy=st.floats(-80, 80), start=st.floats(-90, 90))
@example(bone=1, dx=0.0, dy=0.0, start=88.0)  # bone 1 folded back: its tip lies on the root joint
def test_dragging_a_tip_turns_its_bone_to_point_at_the_mouse(widget, bone, dx, dy, start):
    angles = np.zeros(5)
    angles[bone] = np.radians(start)
    widget.set_pose(angles)
    tip = widget.handle_pixels()["tips"][bone]
    assert widget.press(*(tip + [2.0, -3.0])) == ("tip", bone)
    target = tip + [dx, dy]
    joint = widget.renderer.to_pixels(widget._apply(widget.T, [bone], widget.joints[[bone]]))[0]
    if np.linalg.norm(target - joint) < 5:  # pointing at a spot on the joint has no direction
        return
    widget.drag(*target)
    now = widget.handle_pixels()["tips"][bone]
    assert abs(_turn(now - joint, target - joint)) <= 0.5 + 1e-9  # sliders hold whole degrees
    others = np.delete(np.arange(5), bone)
    assert np.array_equal(np.degrees(widget.angles)[others], np.zeros(4))
    # the mesh follows: the picture's U is the LBS of the dragged pose
    assert np.allclose(widget.U, skinned(widget.V, widget.W, widget.T), atol=1e-12)


def test_dragging_a_root_joint_moves_the_character_with_the_mouse(widget):
    widget.set_pose(np.radians([10.0, -30.0, 0.0, 5.0, 0.0]))
    before = widget.U.copy()
    root = widget.handle_pixels()["roots"][0]
    assert widget.press(*root) == ("root", 0)
    widget.drag(*(root + [30.0, -12.0]))
    moved = widget.handle_pixels()["roots"][0]
    units_per_pixel = 2 * widget.renderer.reach / SIZE[1]
    assert np.abs(moved - (root + [30.0, -12.0])).max() * units_per_pixel <= 0.005 + 1e-9  # whole centimetres
    shift = widget.U - before
    assert np.allclose(shift, shift[0], atol=1e-12)  # a pure translation of every vertex
    widget.release()
    widget.drag(*(root + [90.0, 90.0]))  # released: nothing is grabbed, nothing moves
    assert np.array_equal(widget.handle_pixels()["roots"][0], moved)


def test_a_root_drag_stops_at_the_translation_sliders_range(widget):
    widget.set_pose(np.zeros(5))
    root = widget.handle_pixels()["roots"][0]
    widget.press(*root)
    widget.drag(root[0] + 10 * SIZE[0], root[1])
    assert widget.translation.tolist() == [0.5, 0.0]


def test_a_press_away_from_every_handle_grabs_nothing(widget):
    widget.set_pose(np.zeros(5))
    far = widget.handle_pixels()["tips"][0] + [0.0, -widget.pick_radius - 15]
    assert widget.press(*far) is None
    before = widget.U.copy()
    widget.drag(*(far + [40.0, 40.0]))
    assert np.array_equal(widget.U, before)


def test_browser_mouse_events_drive_press_drag_and_release(widget):
    widget.set_pose(np.zeros(5))
    tip = widget.handle_pixels()["tips"][1]
    widget._mouse_event({"type": "mousedown", "dataX": tip[0], "dataY": tip[1]})
    widget._mouse_event({"type": "mousemove", "dataX": tip[0], "dataY": tip[1] - 60})
    assert np.degrees(widget.angles[1]) != 0
    widget._mouse_event({"type": "mouseleave", "dataX": tip[0] + 60, "dataY": tip[1] - 60})
    turned = np.degrees(widget.angles[1])
    widget._mouse_event({"type": "mousemove", "dataX": tip[0] + 50, "dataY": tip[1]})
    assert np.degrees(widget.angles[1]) == turned


@pytest.mark.parametrize("end", ["mouseup", "mouseleave"])
def test_a_drag_ends_where_the_mouse_was_released_even_if_the_last_move_never_arrived(widget, end):
    # The browser throttles moves but sends the release at once: the release's position must win.
    widget.set_pose(np.zeros(5))
    tip = widget.handle_pixels()["tips"][1]
    joint = widget.renderer.to_pixels(widget._apply(widget.T, [1], widget.joints[[1]]))[0]
    widget._mouse_event({"type": "mousedown", "dataX": tip[0], "dataY": tip[1]})
    widget._mouse_event({"type": "mousemove", "dataX": tip[0] + 5, "dataY": tip[1] - 20})
    target = tip + [20.0, -90.0]
    widget._mouse_event({"type": end, "dataX": target[0], "dataY": target[1]})
    now = widget.handle_pixels()["tips"][1]
    assert abs(_turn(now - joint, target - joint)) <= 0.5 + 1e-9
    widget._mouse_event({"type": "mousemove", "dataX": tip[0], "dataY": tip[1]})  # a late move changes nothing
    assert np.array_equal(widget.handle_pixels()["tips"][1], now)


def browser_event(kind, pixel, box=(640.0, 480.0), decoding=False):
    """What ipyevents sends for a mouse event at a picture pixel, with the picture shown ``box`` CSS pixels large.

    While the browser decodes a new frame the image's natural size reads 0, and
    so do ``dataX`` and ``dataY``.
    """
    scale = np.array(box) / SIZE
    relative = np.rint(np.asarray(pixel) * scale)  # the browser rounds to whole CSS pixels
    data = (0, 0) if decoding else tuple(np.rint(pixel).astype(int))
    return {"type": kind, "relativeX": float(relative[0]), "relativeY": float(relative[1]),
            "boundingRectWidth": box[0], "boundingRectHeight": box[1], "dataX": data[0], "dataY": data[1]}


@pytest.mark.parametrize("box", [(320.0, 240.0), (640.0, 480.0), (200.0, 150.0)])
def test_events_during_a_redraw_still_land_where_the_mouse_is(widget, box):
    # dataX/dataY read (0, 0) while a new frame decodes; the element box does not.
    widget.set_pose(np.zeros(5))
    tip = widget.handle_pixels()["tips"][1]
    joint = widget.renderer.to_pixels(widget._apply(widget.T, [1], widget.joints[[1]]))[0]
    target = tip + [20.0, -90.0]
    widget._mouse_event(browser_event("mousedown", tip, box, decoding=True))
    widget._mouse_event(browser_event("mousemove", tip + [10.0, -45.0], box, decoding=True))
    widget._mouse_event(browser_event("mouseup", target, box, decoding=True))
    now = widget.handle_pixels()["tips"][1]
    # whole degrees on the slider, whole CSS pixels in the event: a degree at most
    assert abs(_turn(now - joint, target - joint)) <= 1.0


def test_an_event_without_any_position_moves_nothing_and_still_ends_a_drag(widget):
    widget.set_pose(np.zeros(5))
    tip = widget.handle_pixels()["tips"][1]
    widget._mouse_event({"type": "mousedown", "dataX": tip[0], "dataY": tip[1]})
    before = widget.U.copy()
    widget._mouse_event({"type": "mousemove"})
    widget._mouse_event({"type": "mouseup"})
    assert np.array_equal(widget.U, before)
    widget._mouse_event({"type": "mousemove", "dataX": tip[0] + 40, "dataY": tip[1]})
    assert np.array_equal(widget.U, before)


def test_a_release_without_a_position_keeps_the_last_moves_pose(widget):
    widget.set_pose(np.zeros(5))
    root = widget.handle_pixels()["roots"][0]
    widget.press(*root)
    widget.drag(*(root + [25.0, 0.0]))
    moved = widget.translation.copy()
    widget.release()
    assert np.array_equal(widget.translation, moved)
    assert moved.tolist() != [0.0, 0.0]
