"""The Python module against the command line and analytic cases (run by ./run test through ctest)."""
import json
import os
import resource
import subprocess
import tempfile

import numpy as np
import pytest

import gimg

GIMG = os.environ["GIMG_BIN"]
DATA = os.environ["GIMG_TEST_DATA"]
TETRA = os.path.join(DATA, "meshes", "tetra.off")


@pytest.fixture(scope="module")
def device():
    return gimg.Device()


def cli_json(*args):
    out = subprocess.run([GIMG, "--quiet", *args, "--json", "-"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def obj_vertices(path):
    """An OBJ file's positions and texture coordinates, as written."""
    with open(path) as obj:
        rows = [line.split() for line in obj]
    return [np.array([[float(x) for x in r[1:]] for r in rows if r and r[0] == key]) for key in ("v", "vt")]


def grid(n, bump=0.0):
    """An n x n vertex grid of the unit square (two triangles a square), its middle raised by `bump`."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = bump * np.exp(-20 * ((x - 0.5) ** 2 + (y - 0.5) ** 2))
    positions = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    return positions, np.array(faces)


def plateau():
    """A 9 x 9 vertex grid with a raised middle: a disk."""
    return grid(9, bump=0.2)


def test_load_mesh_and_info_match_the_command_line():
    positions, faces = gimg.load_mesh(TETRA)
    assert positions.shape == (4, 3) and faces.shape == (4, 3)
    assert positions.dtype == np.float64 and faces.dtype == np.int64
    info = gimg.info(positions, faces)
    cli = cli_json("info", TETRA)
    for key in ("vertices", "faces", "edges", "components", "boundary_loops"):
        assert info[key] == cli[key], key
    assert info["genus"] == [0]


def test_repair_matches_the_command_line(tmp_path):
    part = os.path.join(DATA, "real", "table_part.off")
    positions, faces = gimg.load_mesh(part)
    assert not gimg.info(positions, faces)["manifold"]
    fixed_p, fixed_f, report = gimg.repair(positions, faces, largest=True)
    info = gimg.info(fixed_p, fixed_f)
    assert info["manifold"] and info["oriented"] and info["components"] == 1
    cli = cli_json("repair", part, "--largest", "--out", str(tmp_path / "fixed.ply"))
    for key, value in report.items():
        assert cli["repair"][key] == value, key
    assert cli["after"]["faces"] == len(fixed_f) and cli["after"]["vertices"] == len(fixed_p)


def test_save_then_load_round_trips(tmp_path):
    positions, faces = plateau()
    path = str(tmp_path / "plateau.ply")
    gimg.save_mesh(path, positions, faces.astype(np.int32))  # int32 faces are taken too
    back_p, back_f = gimg.load_mesh(path)
    assert np.array_equal(back_f, faces)
    assert np.allclose(back_p, positions, atol=1e-6)  # PLY stores float32


def test_cylinder_matches_the_command_line(device):
    positions, faces = gimg.load_mesh(TETRA)
    distance, mask, frame = gimg.cylinder(device, positions, faces, width=32, height=16)
    cli = cli_json("cylinder", TETRA, "--size", "32x16", "--out", tempfile.mkdtemp())
    assert distance.shape == (16, 32)
    assert int(mask.sum()) == cli["covered_pixels"]
    assert frame["scale"] == pytest.approx(cli["scale"], rel=1e-15)
    assert np.isnan(distance[~mask]).all() and np.isfinite(distance[mask]).all()


def test_a_planar_square_maps_to_itself(device):
    positions, faces = grid(7)
    for dev in (None, device):
        result = gimg.gim(dev, positions, faces, size=9, variant="floater")
        assert np.abs(result["uv"] - positions[:, :2]).max() < 1e-7
        assert result["flipped"] == 0 and result["covered"].all()


def test_gim_and_quadmap_match_the_command_line(device, tmp_path):
    positions, faces = plateau()
    path = str(tmp_path / "plateau.obj")
    gimg.save_mesh(path, positions, faces)
    positions, faces = gimg.load_mesh(path)  # the same float32-rounded input the command line reads
    result = gimg.gim(device, positions, faces, size=17, variant="density")
    cli = cli_json("gim", path, "--size", "17", "--variant", "density", "--samples", "20000", "--out",
                   str(tmp_path / "gim"))
    assert result["iterations"] == len(cli["iterations"]) - 1
    assert len(result["faces"]) == cli["reconstruction_faces"]
    assert result["selected_iteration"] == cli["selected_iteration"] == result["iterations"]
    chosen = gimg.gim(None, positions, faces, size=17, variant="density", select=True)
    scli = cli_json("gim", path, "--size", "17", "--variant", "density", "--select", "--cpu", "--samples", "20000",
                    "--out", str(tmp_path / "gim_select"))
    assert chosen["selected_iteration"] == scli["selected_iteration"]
    # param.obj: the mesh and the map returned as its texture coordinates, every bit of both.
    v, vt = obj_vertices(tmp_path / "gim_select" / "param.obj")
    assert np.array_equal(v, positions) and np.array_equal(vt, chosen["uv"])
    rms = [it["image_rms"] for it in scli["iterations"]]
    assert rms[scli["selected_iteration"]] == min(rms)
    assert gimg.gim(None, positions, faces, size=0, variant="floater")["image"].shape == (9, 9, 3)  # 81 vertices
    assert gimg.gim(None, positions, faces, variant="floater")["image"].shape == (9, 9, 3)  # the default is size=0
    quad = gimg.quadmap(device, positions, faces, [0, 8, 80, 72], solver="iterate")
    qcli = cli_json("quadmap", path, "--corners", "0,8,80,72", "--solver", "iterate", "--out", str(tmp_path / "q"))
    assert (quad["iterations_u"], quad["iterations_v"]) == (qcli["iterations_u"], qcli["iterations_v"])
    assert len(quad["positions"]) == qcli["region_vertices"] and quad["flipped"] == 0
    assert (quad["uv"] >= 0).all() and (quad["uv"] <= 1).all()
    v, vt = obj_vertices(tmp_path / "q" / "region.obj")
    assert np.array_equal(v, quad["positions"]) and np.array_equal(vt, quad["uv"])


@pytest.mark.parametrize("positions, faces, message", [
    (np.zeros((4, 2)), [[0, 1, 2]], "N x 3"),
    ([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]], "not finite"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], "names vertex 3"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.zeros((0, 3)), "no faces"),
])
def test_bad_arrays_raise_value_error(positions, faces, message):
    with pytest.raises(ValueError, match=message):
        gimg.info(np.asarray(positions, dtype=float), np.asarray(faces))


def test_gim_cuts_a_closed_mesh_open_as_the_command_line_does(device, tmp_path):
    positions, faces = gimg.load_mesh(TETRA)
    result = gimg.gim(device, positions, faces, size=5, cut=True)
    cli = cli_json("gim", TETRA, "--cut", "--size", "5", "--out", str(tmp_path / "gim"))
    assert (result["cut_edges"], result["cut_paths"]) == (cli["cut"]["edges"], cli["cut"]["paths"])
    assert result["seam_joined"] and cli["cut"]["seam_joined"]
    assert len(result["faces"]) == cli["reconstruction_faces"]
    assert len(result["disk_positions"]) == len(result["uv"]) == cli["cut"]["disk_vertices"]
    assert result["flipped"] == cli["flipped"] == 0
    copied = result["source"] >= 0
    assert np.array_equal(result["disk_positions"][copied], positions[result["source"][copied]])
    v, vt = obj_vertices(tmp_path / "gim" / "param.obj")  # the opened mesh and its map
    assert np.array_equal(vt, result["uv"])


def torus(ring=24, tube=8, R=2.0, r=0.6):
    """A torus of ring x tube vertices."""
    a, b = np.meshgrid(np.arange(ring) * 2 * np.pi / ring, np.arange(tube) * 2 * np.pi / tube, indexing="ij")
    d = R + r * np.cos(b)
    positions = np.stack([d * np.cos(a), r * np.sin(b), -d * np.sin(a)], axis=2).reshape(-1, 3)
    faces = []
    for i in range(ring):
        for j in range(tube):
            v = lambda di, dj: ((i + di) % ring) * tube + (j + dj) % tube
            faces += [[v(0, 0), v(1, 0), v(1, 1)], [v(0, 0), v(1, 1), v(0, 1)]]
    return positions, np.array(faces)


@pytest.mark.parametrize("graph, select", [("face-tree", False), ("shortest-loops", False), ("best", False),
                                           ("best", True)])
def test_gim_takes_the_cut_graph_the_command_line_does(device, tmp_path, graph, select):
    path = tmp_path / "torus.ply"
    gimg.save_mesh(str(path), *torus())
    positions, faces = gimg.load_mesh(str(path))  # as the command line reads it
    result = gimg.gim(device, positions, faces, size=17, cut=True, cut_graph=graph, select=select)
    cli = cli_json("gim", str(path), "--cut", "--cut-graph", graph, "--size", "17", "--out", str(tmp_path / "gim"),
                   *(["--select"] if select else []))
    assert len(cli["cut"]["graph_image_rms"]) == (2 if select else 0)
    assert result["cut_graph"] == cli["cut"]["graph"]
    if graph != "best":
        assert result["cut_graph"] == graph.replace("-", " ")
    assert (result["cut_edges"], result["cut_paths"]) == (cli["cut"]["edges"], cli["cut"]["paths"])
    with pytest.raises(ValueError, match="cut_graph must be"):
        gimg.gim(device, positions, faces, size=17, cut=True, cut_graph="spiral")


def test_refusals_and_the_device_error_type(device):
    positions, faces = gimg.load_mesh(TETRA)
    with pytest.raises(ValueError, match="this mesh is closed"):
        gimg.gim(device, positions, faces)
    assert issubclass(gimg.DeviceError, RuntimeError)
    with pytest.raises(gimg.DeviceError):
        gimg.Device("no device is called this")


def test_a_thousand_calls_do_not_grow_memory():
    positions, faces = plateau()
    for _ in range(100):
        gimg.info(positions, faces)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(1000):
        gimg.info(positions, faces)
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 10_000  # kilobytes


def test_the_example_in_docs_python_md_runs(capsys):
    root = os.path.dirname(os.path.dirname(DATA.rstrip("/")))  # tests/data -> the checkout
    text = open(os.path.join(root, "docs", "python.md")).read()
    block = text.split("<!-- python-example -->")[1].split("<!-- /python-example -->")[0]
    code = block.split("```python\n")[1].split("```")[0]
    cwd = os.getcwd()
    os.chdir(root)
    try:
        exec(compile(code, "docs/python.md", "exec"), {})
    finally:
        os.chdir(cwd)
    assert "[0]" in capsys.readouterr().out


def test_compare_and_sphere_match_the_command_line():
    cube = os.path.join(DATA, "meshes", "cube_quads.obj")
    a, b = gimg.load_mesh(TETRA), gimg.load_mesh(cube)
    d = gimg.compare(*a, *b, samples=5000)
    cli = cli_json("compare", TETRA, cube, "--samples", "5000")
    for side in ("a_to_b", "b_to_a"):
        for key in ("mean", "rms", "max"):
            assert d[side][key] == cli[side][key], (side, key)
    points, metrics = gimg.sphere(None, *b, method="linear")
    scli = cli_json("sphere", cube, "--method", "linear", "--out", tempfile.mkdtemp())
    assert np.allclose(np.linalg.norm(points, axis=1), 1.0)
    assert metrics["flips"] == scli["flips"]
    assert metrics["conformal_energy"] == pytest.approx(scli["conformal_energy"], rel=1e-12)


def test_sample_reconstruct_and_render(device):
    # A planar grid with identity parameters: pixel (i, j) holds ((i + 0.5) / N, 1 - (j + 0.5) / N, 0).
    positions, faces = grid(6)
    size = 16
    for dev in (None, device):
        s = gimg.sample(dev, positions, faces, positions[:, :2], size=size)
        assert s["covered"].all()
        centres = (np.arange(size) + 0.5) / size
        assert np.abs(s["image"][:, :, 0] - centres[None, :]).max() < 1e-6
        assert np.abs(s["image"][:, :, 1] - (1 - centres)[:, None]).max() < 1e-6
        back_p, back_f = gimg.reconstruct(dev, s["image"], s["covered"])
        assert back_p.shape == (size * size, 3) and back_f.shape == (2 * (size - 1) ** 2, 3)
    picture = gimg.render(device, positions, faces, width=64, height=48)
    assert picture.shape == (48, 64, 4) and picture.dtype == np.uint8
    assert (picture[:, :, 3] > 0).any() and (picture[:, :, 3] == 0).any()
    with pytest.raises(ValueError, match="N x 2"):
        gimg.sample(None, positions, faces, positions, size=size)


def test_cylinder_reconstruction_and_deform(device):
    positions, faces = gimg.load_mesh(os.path.join(DATA, "meshes", "cube_quads.obj"))
    distance, mask, frame = gimg.cylinder(device, positions, faces, width=64, height=32)
    gpu_p, gpu_f = gimg.reconstruct_cylinder(device, distance, frame)
    cpu_p, cpu_f = gimg.reconstruct_cylinder(None, distance, frame)
    assert np.array_equal(gpu_f, cpu_f) and np.abs(gpu_p - cpu_p).max() < 1e-5
    # The rebuilt points lie on the cube [0, 1]^3's surface (the model's own coordinates): each has a
    # coordinate at 0 or 1, within the reconstruction's flattening of the edges.
    assert (np.minimum(np.abs(cpu_p), np.abs(cpu_p - 1)).min(axis=1) < 0.02).mean() > 0.95
    assert (cpu_p > -0.05).all() and (cpu_p < 1.05).all()
    grid, tris = plateau()
    bumped = gimg.deform(None, grid, tris, [0, 8, 80, 72], paste_height=0.05)
    assert bumped.shape == grid.shape
    moved = np.linalg.norm(bumped - grid, axis=1)
    border = (grid[:, 0] == 0) | (grid[:, 0] == 1) | (grid[:, 1] == 0) | (grid[:, 1] == 1)
    assert moved[border].max() == 0.0 and moved.max() > 0.01
    assert np.abs(gimg.deform(device, grid, tris, [0, 8, 80, 72], paste_height=0.05) - bumped).max() < 1e-12
    zero = gimg.deform(device, grid, tris, [0, 8, 80, 72], offsets=np.zeros((8, 8, 3)))
    assert np.array_equal(zero, grid)


def test_maps_remeshes_a_closed_mesh_on_its_surface(device):
    positions, faces = gimg.load_mesh(os.path.join(DATA, "meshes", "tetra.off"))
    gpu = gimg.maps(device, positions, faces, levels=2)
    cpu = gimg.maps(None, positions, faces, levels=2)
    base_positions, base_faces = gpu["base"]
    assert len(base_faces) == 4  # a tetrahedron is its own base domain
    for j, (p, f) in enumerate(gpu["levels"]):
        assert len(f) == 4 * 4**j
    finest, finest_faces = gpu["levels"][2]
    np.testing.assert_allclose(finest, cpu["levels"][2][0], atol=1e-12)
    # Every remesh point lies on a face of the tetrahedron: on one of its four planes, inside.
    on_plane = np.zeros(len(finest), dtype=bool)
    for t in faces:
        a, b, c = positions[t]
        n = np.cross(b - a, c - a)
        on_plane |= np.abs((finest - a) @ n) <= 1e-12 * np.linalg.norm(n)
    assert on_plane.all()
    assert gpu["fallbacks"] == 0
    assert gpu["coefficients"].shape == finest.shape
    np.testing.assert_allclose(gpu["coefficients"][:4], base_positions, atol=1e-12)  # a linear subdivision: c^0 = base
    with pytest.raises(ValueError, match="closed 2-manifold"):
        grid_positions, grid_faces = gimg.load_mesh(os.path.join(DATA, "meshes", "quad_uv.obj"))
        gimg.maps(None, grid_positions, grid_faces)


def test_roundtrip_batches_and_retrieval_match_the_command_line(device, tmp_path):
    positions, faces = gimg.load_mesh(TETRA)
    r = gimg.roundtrip(device, positions, faces, width=64, height=32, samples=20000)
    cli = cli_json("roundtrip", TETRA, "--size", "64x32", "--samples", "20000", "--out", str(tmp_path / "rt"))
    assert len(r["faces"]) == cli["reconstruction_faces"]
    assert r["rms_to_reconstruction"] == pytest.approx(cli["a_to_b"]["rms"] / cli["bbox_diagonal"], rel=1e-12)
    assert r["rms_back"] == pytest.approx(cli["b_to_a"]["rms"] / cli["bbox_diagonal"], rel=1e-12)
    # A flat square: the cylinder's rays only graze it, and what the image rebuilds has no area.
    flat_positions, flat_faces = gimg.load_mesh(os.path.join(DATA, "meshes", "quad_uv.obj"))
    with pytest.raises(ValueError, match="rebuilds only faces of no area"):
        gimg.roundtrip(device, flat_positions, flat_faces, width=64, height=32)

    # A list in one call gives what one call per mesh gives, bit for bit.
    names = ["cube_quads.obj", "quad_uv.obj", "tetra.off", "tetra_colors.off"]
    meshes = [gimg.load_mesh(os.path.join(DATA, "meshes", n)) for n in names]
    for (p, f), (d, m, fr) in zip(meshes, gimg.cylinder_batch(device, meshes, width=32, height=16)):
        d1, m1, fr1 = gimg.cylinder(device, p, f, width=32, height=16)
        np.testing.assert_array_equal(m, m1)
        np.testing.assert_array_equal(d[m], d1[m1])
        assert fr["scale"] == fr1["scale"]

    # The index of the same models ranks a query as gimg index + gimg search do.
    folder = tmp_path / "models"
    folder.mkdir()
    for n in names:
        (folder / n).write_bytes(open(os.path.join(DATA, "meshes", n), "rb").read())
    subprocess.run([GIMG, "--quiet", "index", str(folder), "--out", str(tmp_path / "db.json"), "--size", "32",
                    "--reduced", "8"], check=True)
    found = cli_json("search", str(tmp_path / "db.json"), os.path.join(DATA, "meshes", "cube_quads.obj"))["results"]
    db = gimg.index(device, meshes, size=32, reduced=8)
    assert db.size == len(names)
    ours = db.search(device, *meshes[0], k=len(names))
    assert [names[i] for i, _ in ours] == [os.path.basename(x["path"]) for x in found]
    assert [d for _, d in ours] == pytest.approx([x["distance"] for x in found], rel=1e-6, abs=1e-9)
    db.save(str(tmp_path / "py.json"))
    assert gimg.load_database(str(tmp_path / "py.json")).k == db.k

    # The panorama descriptor ranks as gimg index --descriptor panorama does, and a bad name is refused.
    subprocess.run([GIMG, "--quiet", "index", str(folder), "--out", str(tmp_path / "pano.json"), "--descriptor",
                    "panorama"], check=True)
    found = cli_json("search", str(tmp_path / "pano.json"), os.path.join(DATA, "meshes", "cube_quads.obj"))["results"]
    pano = gimg.index(device, meshes, descriptor="panorama")
    assert pano.k == 6 * 21 * 21
    ours = pano.search(device, *meshes[0], k=len(names))
    assert [names[i] for i, _ in ours] == [os.path.basename(x["path"]) for x in found]
    assert ours[0][1] == pytest.approx(0.0, abs=1e-6)  # the cube itself first
    with pytest.raises(ValueError, match="descriptor"):
        gimg.index(device, meshes, descriptor="zernike")


def test_the_walkthrough_in_docs_python_md_draws_its_pictures(capsys, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    root = os.path.dirname(os.path.dirname(DATA.rstrip("/")))
    text = open(os.path.join(root, "docs", "python.md")).read()
    block = text.split("<!-- python-walkthrough -->")[1].split("<!-- /python-walkthrough -->")[0]
    code = block.split("```python\n")[1].split("```")[0]
    monkeypatch.setenv("GIMG_WALKTHROUGH_OUT", str(tmp_path))
    exec(compile(code, "docs/python.md", "exec"), {})
    printed = capsys.readouterr().out
    assert "[0]" in printed and "0 flipped triangles" in printed
    for name in ("cylinder.png", "sphere.png"):
        picture = tmp_path / name
        assert picture.stat().st_size > 10000  # a real plot, not an empty canvas


def test_hierarchical_images_match_on_the_device_and_the_command_line(device, tmp_path):
    positions, faces = gimg.load_mesh(os.path.join(DATA, "meshes", "cube_quads.obj"))
    gpu = gimg.cylinder_hierarchy(device, positions, faces, size=32, base=8)
    cpu = gimg.cylinder_hierarchy(None, positions, faces, size=32, base=8)
    np.testing.assert_array_equal(gpu["t"], cpu["t"])  # the GPU rays give the CPU's hierarchy bit for bit
    np.testing.assert_array_equal(gpu["valid"], cpu["valid"])
    assert gpu["levels"] == 3 and len(gpu["faces"]) > 0
    cli = cli_json("cylinder", os.path.join(DATA, "meshes", "cube_quads.obj"), "--method", "hierarchical",
                   "--size", "32", "--base", "8", "--out", str(tmp_path / "h"))
    assert int(np.count_nonzero(gpu["valid"])) == cli["valid_samples"]
    assert gpu["frame"]["scale"] == cli["scale"]


def test_evaluate_gives_the_command_line_scores(device, tmp_path):
    # Two classes of two models each, in folders named for them: leave-one-out as gimg eval scores it.
    shapes = {"box": ["cube_quads.obj", "tetra_ascii.ply"], "flat": ["quad_uv.obj", "tetra.off"]}
    paths = []
    for label, names in shapes.items():
        (tmp_path / "models" / label).mkdir(parents=True)
        for n in names:
            (tmp_path / "models" / label / n).write_bytes(open(os.path.join(DATA, "meshes", n), "rb").read())
            paths.append((str(tmp_path / "models" / label / n), label))
    paths.sort()
    subprocess.run([GIMG, "--quiet", "index", str(tmp_path / "models"), "--out", str(tmp_path / "db.json"),
                    "--size", "32", "--reduced", "8"], check=True)
    cli = cli_json("eval", str(tmp_path / "db.json"))
    db = gimg.index(device, [gimg.load_mesh(p) for p, _ in paths], labels=[l for _, l in paths], size=32, reduced=8)
    ours = db.evaluate(device, [gimg.load_mesh(p) for p, _ in paths])
    assert ours["queries"] == 4
    for key in ("nn", "first_tier", "second_tier", "dcg", "map"):
        assert ours[key] == pytest.approx(cli["overall"][key], abs=1e-12), key


def test_polycube_of_an_open_tube_keeps_its_ends(device, tmp_path):
    # An upright tube of 32 x 8 quads, open at both ends: a box-like polycube whose top and bottom
    # hold the two holes, every vertex mapped onto its surface, on the device as by the CPU twins.
    around, rows = 32, 8
    t = np.arange(around) * 2 * np.pi / around
    positions = np.array([[np.cos(a), np.sin(a), -1 + 2 * r / rows] for r in range(rows + 1) for a in t])
    faces = []
    for r in range(rows):
        for a in range(around):
            v00, v01 = r * around + a, r * around + (a + 1) % around
            v10, v11 = v00 + around, v01 + around
            faces += [[v00, v01, v11], [v00, v11, v10]]
    faces = np.array(faces, dtype=np.uint32)
    gpu = gimg.polycube(device, positions, faces, da=10.0)
    cpu = gimg.polycube(None, positions, faces, da=10.0)
    assert gpu["holes"] == 2 and gpu["holes_marked"] == 2
    assert gpu["polycube_faces"] == 6 and gpu["polycube_corners"] == 8
    assert gpu["flips"] == 0
    assert gpu["attempts"] == 1 and gpu["slice_smoothing"] == 0  # built on the first try, on the mesh itself
    box_min = gpu["polycube"][0].min(axis=0)
    box_max = gpu["polycube"][0].max(axis=0)
    m = gpu["mapped"]
    assert np.all((m >= box_min - 1e-9) & (m <= box_max + 1e-9))
    assert np.all(np.minimum(np.abs(m - box_min), np.abs(m - box_max)).min(axis=1) < 1e-9)
    assert np.abs(gpu["mapped"] - cpu["mapped"]).max() < 1e-4
    with pytest.raises(ValueError):
        gimg.polycube(None, positions, faces, axis="w")
    # mapped.ply holds the images in float64, every bit of the map the CPU twins give.
    path = str(tmp_path / "tube.obj")
    gimg.save_mesh(path, positions, faces)
    positions, faces = gimg.load_mesh(path)  # as the command line reads it
    cli_json("polycube", path, "--da", "10", "--cpu", "--out", str(tmp_path / "tube"))
    with open(tmp_path / "tube" / "mapped.ply", "rb") as ply:
        data = ply.read()
    header, body = data.split(b"end_header\n", 1)
    assert b"property double x" in header
    mapped = np.frombuffer(body, dtype="<f8", count=3 * len(positions)).reshape(-1, 3)
    assert np.array_equal(mapped, gimg.polycube(None, positions, faces, da=10.0)["mapped"])


def test_batch_runs_a_function_over_a_list_as_gimg_batch_does(device, tmp_path):
    # Files as gimg batch reads them: the same results in order, and a broken file's message kept.
    folder = tmp_path / "models"
    folder.mkdir()
    for n in ["cube_quads.obj", "tetra.off"]:
        (folder / n).write_bytes(open(os.path.join(DATA, "meshes", n), "rb").read())
    (folder / "broken.off").write_text("OFF garbage\n")
    subprocess.run([GIMG, "--quiet", "batch", "info", "--inputs", str(folder), "--out", str(tmp_path / "run")],
                   check=True)
    lines = [json.loads(x) for x in open(tmp_path / "run" / "results.jsonl")]
    by_input = {x["input"]: x for x in lines}
    paths = sorted(folder.iterdir())
    results = gimg.batch(gimg.info, paths, errors="keep")
    assert len(results) == 3
    for path, result in zip(paths, results):
        line = by_input[path.name]
        if line["status"] == "failed":
            assert isinstance(result, ValueError) and str(result) == line["error"]
        else:
            for key in ["vertices", "faces", "edges", "genus", "closed", "manifold"]:
                assert result[key] == line["result"][key]
    with pytest.raises(ValueError, match="OFF counts must be three whole numbers"):
        gimg.batch(gimg.info, paths)

    # Arrays: each result is the single call's; a bad mesh keeps its ValueError in place with
    # errors="keep", and ends the run with the default.
    positions, faces = gimg.load_mesh(TETRA)
    meshes = [(positions * (1 + 0.25 * k), faces) for k in range(4)]
    spheres = gimg.batch(gimg.sphere, meshes, device=device)
    for (p, f), (points, metrics) in zip(meshes, spheres):
        np.testing.assert_array_equal(points, gimg.sphere(device, p, f)[0])
        assert metrics["flips"] == 0
    bad = meshes[:2] + [(positions, faces + 10)] + meshes[2:]
    for function, options in [(gimg.cylinder, {"device": device, "width": 32, "height": 16}),
                              (gimg.sphere, {"device": device})]:
        kept = gimg.batch(function, bad, errors="keep", **options)
        assert [type(r) for r in kept] == [tuple, tuple, ValueError, tuple, tuple]
        assert str(kept[2]) == "face 0 names vertex 10 of 4"
        with pytest.raises(ValueError, match="face 0 names vertex 10 of 4"):
            gimg.batch(function, bad, **options)
    # cylinder's list is projected in one batch, bit for bit the single calls.
    for (p, f), (d, m, fr) in zip(meshes, gimg.batch(gimg.cylinder, meshes, device=device, width=32, height=16)):
        d1, m1, fr1 = gimg.cylinder(device, p, f, width=32, height=16)
        np.testing.assert_array_equal(m, m1)
        np.testing.assert_array_equal(d[m], d1[m1])
        assert fr["scale"] == fr1["scale"]
    with pytest.raises(ValueError, match='errors must be "raise" or "keep"'):
        gimg.batch(gimg.info, meshes, errors="ignore")
    with pytest.raises(ValueError, match="a list of \\(positions, faces\\) pairs or mesh file paths"):
        gimg.batch(gimg.info, [positions])
