"""Tests of the Python module `immersion` (run by ctest: python_immersion).

Every verb (read, build_complex, find_immersions, mesh_immersion, Mesh.write) on arrays and on
files; bad arrays (wrong shape, dtype, NaN, open surface, index out of range) and not-immersible
inputs as exceptions with `kind` and `exit_code`; and the same input through the `immerse`
program (IMM_IMMERSE), whose messages (without "immerse: ") and output files must be identical.
Invariants are checked here from the arrays alone: windings x areas = enclosed area (exact, from
the 'p/q' strings), nodes per cell = winding, every patch owned once, the embedding reproduces the
input, every element positively oriented.
"""
import fractions
import os
import subprocess
import tempfile
import unittest

import numpy as np

import immersion

IMMERSE = os.environ.get("IMM_IMMERSE", "immerse")


def run_immerse(*args):
    return subprocess.run([IMMERSE, *args], capture_output=True, text=True)


def cli_message(stderr):
    """The program's verdict/defect message: stderr from its first 'immerse: ' line, without the
    prefix, up to the summary line."""
    lines = stderr.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("immerse: ") and "note:" not in l)
    body = [lines[start][len("immerse: "):]]
    for line in lines[start + 1:]:
        if line.startswith("immerse: "):
            break
        body.append(line)
    return "\n".join(body)


def squares():
    """Two overlapping counter-clockwise squares: cells of winding 1, 1, 2."""
    return [np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float),
            np.array([[1, 1], [3, 1], [3, 3], [1, 3]], float)]


def cube():
    V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], np.int64)
    return V, F


class Fixture(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def generate(self, name, *params, ext=".obj"):
        out = self.path(name + "_" + "_".join(params) + ext)
        if not os.path.exists(out):
            r = run_immerse("generate", name, *params, "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
        return out


class Arrays2D(Fixture):
    def test_complex_counts_windings_and_exact_areas(self):
        c = immersion.build_complex(immersion.Curves(squares()))
        self.assertEqual((c.dimension, c.cells, c.max_winding), (2, 3, 2))
        self.assertEqual(sorted(c.windings.tolist()), [1, 1, 2])
        areas = [fractions.Fraction(q) for q in c.volumes_exact]
        # Invariant 1: sum of winding x area = the signed area enclosed by the curves (4 + 4).
        self.assertEqual(sum(w * a for w, a in zip(c.windings.tolist(), areas)), 8)
        np.testing.assert_allclose(c.volumes, [float(a) for a in areas])
        self.assertEqual(c.patch_regions.shape, (c.patches, 2))

    def test_immersions_and_mesh_with_embedding(self):
        curves = immersion.Curves(squares())
        found = immersion.find_immersions(curves)
        self.assertEqual(len(found), 1)
        g = found.graphs[0]
        windings = found.complex.windings
        # Nodes per cell = winding number; every patch owned by a node of one of its sides' cells.
        self.assertEqual(np.bincount(g["node_cell"], minlength=found.complex.cells).tolist(),
                         windings.tolist())
        self.assertEqual(g["patch_owner"].shape, (found.complex.patches,))
        self.assertEqual(g["edges"].shape[1], 3)
        mesh = immersion.mesh_immersion(found, resolution=12)
        V, T = mesh.V, mesh.T
        self.assertEqual((V.shape[1], T.shape[1], V.dtype, T.dtype), (2, 3, np.float64, np.int32))
        self.assertEqual(mesh.node.shape, (T.shape[0],))
        # Positive orientation of every triangle.
        a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
        cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
        self.assertTrue((cross > 0).all())
        # The embedding reproduces the 8 input vertices.
        inputs = np.concatenate(squares())
        e, w = mesh.embedding_element, mesh.embedding_weights
        self.assertEqual(w.shape, (8, 3))
        rebuilt = np.einsum("ik,ikd->id", w, V[T[e]])
        np.testing.assert_allclose(rebuilt, inputs, atol=1e-9 * 3)

    def test_all_immersions_of_fig6(self):
        path = self.generate("fig6", ext=".txt")
        curves = immersion.read_curves(path)
        self.assertEqual(curves.name, path)
        found = immersion.find_immersions(curves, max=0)
        self.assertEqual((len(found), found.complete), (2, True))
        cli = run_immerse("immersions", path, "--all")
        self.assertEqual(cli.returncode, 0)
        self.assertIn("2 immersions", cli.stdout)

    def test_figure_eight_inverts_space(self):
        eight = [np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float)]
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(immersion.Curves(eight, name="eight"))
        self.assertEqual((e.exception.kind, e.exception.exit_code), ("not-immersible", 3))
        self.assertTrue(str(e.exception).startswith("'eight' is not immersible: "))
        self.assertIsInstance(e.exception, immersion.Error)

    def test_not_immersible_message_is_the_programs(self):
        path = self.generate("fig8", ext=".txt")
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 3)
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(immersion.read_curves(path))
        self.assertEqual(str(e.exception), cli_message(cli.stderr))

    def test_bad_curves(self):
        for bad in ([np.zeros((4, 3))], [np.zeros(4)], [np.array([["a", "b"]])]):
            with self.assertRaises(immersion.InvalidInput) as e:
                immersion.Curves(bad)
            self.assertIsInstance(e.exception, ValueError)
            self.assertEqual(e.exception.exit_code, 2)
        nan = [np.array([[0, 0], [1, 0], [np.nan, 1]], float)]
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.build_complex(immersion.Curves(nan))
        self.assertIn("non-finite", str(e.exception))


class Arrays3D(Fixture):
    def test_surface_round_trip_of_arrays(self):
        V, F = cube()
        s = immersion.Surface(V, F.astype(np.int32), name="cube")
        np.testing.assert_array_equal(s.V, V)
        np.testing.assert_array_equal(s.F, F)
        c = immersion.build_complex(s)
        self.assertEqual((c.cells, c.max_winding, c.arcs), (1, 1, 0))
        self.assertEqual(fractions.Fraction(c.volumes_exact[0]), 1)

    def test_bad_arrays(self):
        V, F = cube()
        cases = [
            (lambda: immersion.Surface(V[:, :2], F), "shape (n, 3), got (8, 2)"),
            (lambda: immersion.Surface(V, F[:, :2]), "shape (m, 3), got (12, 2)"),
            (lambda: immersion.Surface(V, F.astype(float)), "must hold integers"),
            (lambda: immersion.Surface(V.ravel(), F), "got (24,)"),
        ]
        for make, text in cases:
            with self.assertRaises(immersion.InvalidInput) as e:
                make()
            self.assertIn(text, str(e.exception))
            self.assertEqual((e.exception.kind, e.exception.exit_code), ("invalid-input", 2))
            self.assertIsInstance(e.exception, ValueError)
        nan = V.copy()
        nan[3, 1] = np.nan
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.build_complex(immersion.Surface(nan, F))
        self.assertIn("non-finite", str(e.exception))
        out_of_range = F.copy()
        out_of_range[5, 2] = 8
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.find_immersions(immersion.Surface(V, out_of_range))
        self.assertIn("triangle 5 refers to vertex 8", str(e.exception))
        # Indices past an int were named "vertex -1" (clamped); uint64 past 2^63 wrapped.
        for dtype, index in ((np.int64, 2**40), (np.uint64, 2**64 - 1), (np.uint64, 2**63 + 5)):
            huge = F.astype(dtype)
            huge[5, 2] = index
            with self.assertRaises(immersion.InvalidInput) as e:
                immersion.find_immersions(immersion.Surface(V, huge))
            self.assertIn("triangle 5 refers to vertex %d" % index, str(e.exception))

    def test_mesh_options_are_bounded_like_the_program(self):
        # resolution 0 failed an internal invariant (InternalError), 10**6 an allocation check, and
        # threads=10**9 allocated per-thread scratch until the process was killed.
        V, F = cube()
        found = immersion.find_immersions(immersion.Surface(V, F))
        for options, text in ((dict(resolution=0), "resolution expects 1..150, got 0"),
                              (dict(resolution=10**6), "resolution expects 1..150"),
                              (dict(threads=10**9), "threads: at most 1024")):
            with self.assertRaises(immersion.InvalidInput) as e:
                immersion.mesh_immersion(found, **options)
            self.assertIn(text, str(e.exception))
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.find_immersions(immersion.Surface(V, F), threads=10**9)
        self.assertIn("threads: at most 1024", str(e.exception))
        with self.assertRaises(immersion.InvalidInput):
            immersion.mesh_immersion(immersion.find_immersions(immersion.Curves(squares())), resolution=0)
        # resolution and background together: `immerse mesh` exits 64; was accepted (background won).
        with open(self.path("bg.mesh"), "w") as f:
            f.write("MeshVersionFormatted 1\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\nTriangles\n1\n1 2 3 0\nEnd\n")
        for found_any in (found2 := immersion.find_immersions(immersion.Curves(squares())), found):
            with self.assertRaises(ValueError) as e:
                immersion.mesh_immersion(found_any, resolution=4, background=self.path("bg.mesh"))
            self.assertNotIsInstance(e.exception, immersion.Error)
            self.assertIn("resolution and background exclude each other", str(e.exception))
        # Curves take the surfaces' keywords and refuse the 3D-only ones by name (was a TypeError).
        found2 = immersion.find_immersions(immersion.Curves(squares()))
        for options in (dict(conforming=True, edge_length=0.1), dict(surface_resolution=8), dict(min_dihedral=5.0)):
            with self.assertRaises(immersion.InvalidInput) as e:
                immersion.mesh_immersion(found2, **options)
            self.assertIn(f"{list(options)[-1]} is for 3D surfaces only", str(e.exception))

    def test_open_surface_message_is_the_programs(self):
        V, F = cube()
        path = self.path("open.obj")
        with open(path, "w") as f:
            f.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V)
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F[:-1])
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 2)
        for surface in (immersion.read_surface(path), immersion.Surface(V, F[:-1], name=path)):
            with self.assertRaises(immersion.InvalidInput) as e:
                immersion.find_immersions(surface)
            self.assertEqual(str(e.exception), cli_message(cli.stderr))
            self.assertIn("not-closed (validate): open boundary", str(e.exception))

    def test_inverted_surface_is_not_immersible_like_the_program(self):
        path = self.generate("limacon-torus", "16")
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 3)
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(immersion.read_surface(path))
        self.assertEqual(str(e.exception), cli_message(cli.stderr))

    def test_mesh_is_the_programs_byte_for_byte(self):
        path = self.generate("two-spheres", "8")
        surface = immersion.read_surface(path)
        found = immersion.find_immersions(surface)
        c = found.complex
        self.assertEqual((c.cells, sorted(c.windings.tolist())), (3, [1, 1, 2]))
        g = found.graphs[0]
        self.assertEqual(len(g["node_cell"]), 4)
        mesh = immersion.mesh_immersion(found, resolution=5)
        for ext in (".mesh", ".msh", ".vtu", ".veg", ".node"):
            mesh.write(self.path("py" + ext))
            cli = run_immerse("mesh", path, "--resolution", "5", "-o", self.path("cli" + ext),
                              "--embedding", self.path("cli.emb"))
            self.assertEqual(cli.returncode, 0, cli.stderr)
            for written in [ext] + ([".ele"] if ext == ".node" else []):
                with open(self.path("py" + written), "rb") as a, open(self.path("cli" + written), "rb") as b:
                    self.assertEqual(a.read(), b.read(), written)
        # Tets positive, embedding reproduces the input, nodes are graph nodes.
        V, T = mesh.V, mesh.T
        self.assertEqual((V.shape[1], T.shape[1]), (3, 4))
        d = np.einsum("ij,ij->i", np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]),
                      V[T[:, 3]] - V[T[:, 0]])
        self.assertTrue((d > 0).all())
        self.assertTrue(set(mesh.node.tolist()) <= set(range(4)))
        rebuilt = np.einsum("ik,ikd->id", mesh.embedding_weights, V[T[mesh.embedding_element]])
        diagonal = np.linalg.norm(surface.V.max(0) - surface.V.min(0))
        np.testing.assert_allclose(rebuilt, surface.V, atol=1e-9 * diagonal)
        with open(self.path("cli.emb")) as f:
            rows = f.read().split("\n")[1:]
        elements = [int(r.split()[0]) for r in rows if r.strip()]
        self.assertEqual(elements, mesh.embedding_element.tolist())

    def test_graded_mesh_is_the_programs_byte_for_byte(self):
        path = self.generate("two-spheres", "8")
        found = immersion.find_immersions(immersion.read_surface(path))
        mesh = immersion.mesh_immersion(found, resolution=2, surface_resolution=8, gap_resolution=16)
        mesh.write(self.path("new/dir/py_graded.mesh"))  # missing directories are made, as by the program
        cli = run_immerse("mesh", path, "--resolution", "2", "--surface-resolution", "8",
                          "--gap-resolution", "16", "-o", self.path("cli_graded.mesh"))
        self.assertEqual(cli.returncode, 0, cli.stderr)
        with open(self.path("new/dir/py_graded.mesh"), "rb") as a, open(self.path("cli_graded.mesh"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        with self.assertRaises(immersion.InvalidInput):
            immersion.mesh_immersion(found, surface_resolution=8, background=self.path("x.veg"))
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.mesh_immersion(found, resolution=8, surface_resolution=4)
        self.assertIn("graded background: surface_resolution 4 is coarser than resolution 8", str(e.exception))

    def test_conforming_mesh_is_the_programs_byte_for_byte(self):
        path = self.generate("two-spheres", "8")
        found = immersion.find_immersions(immersion.read_surface(path))
        mesh = immersion.mesh_immersion(found, conforming=True, resolution=6)
        mesh.write(self.path("pyc.mesh"))
        cli = run_immerse("mesh", path, "--conforming", "--resolution", "6", "-o", self.path("clic.mesh"))
        self.assertEqual(cli.returncode, 0, cli.stderr)
        with open(self.path("pyc.mesh"), "rb") as a, open(self.path("clic.mesh"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        # Every input vertex is a mesh vertex: weight 1 at one corner.
        self.assertTrue(np.allclose(mesh.embedding_weights.max(axis=1), 1.0))
        with self.assertRaises(immersion.InvalidInput):
            immersion.mesh_immersion(found, conforming=True, radius_edge=0.5)
        with self.assertRaises(immersion.InvalidInput):
            immersion.mesh_immersion(found, conforming=True, method="csg")

    def test_immersion_index_and_method_are_checked(self):
        found = immersion.find_immersions(immersion.read_surface(self.generate("two-spheres", "8")))
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.mesh_immersion(found, immersion=3)
        self.assertIn("has only 1 immersion", str(e.exception))
        # The library names its own parameter, not the program's flag.
        self.assertTrue(str(e.exception).startswith("immersion 3: "), str(e.exception))
        with self.assertRaises(immersion.InvalidInput):
            immersion.mesh_immersion(found, method="nef")
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.mesh_immersion(found, background=self.path("missing.veg"))
        self.assertIn("missing.veg", str(e.exception))

    def test_read_errors(self):
        with self.assertRaises(immersion.InvalidInput) as e:
            immersion.read_surface(self.path("nothing.obj"))
        self.assertIn("nothing.obj", str(e.exception))

SHARED = os.environ.get("IMM_SHARED_DATA", "")


class Folds(Fixture):
    def test_local_fold_is_repaired_only_when_asked_like_the_program(self):
        path = self.generate("folded-bipyramid", "100")
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 3)
        surface = immersion.read_surface(path)
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(surface)
        self.assertEqual(str(e.exception), cli_message(cli.stderr))
        found = immersion.find_immersions(surface, repair_folds=3.0)
        self.assertEqual(found.complex.cells, 1)
        cli = run_immerse("immersions", path, "--repair-folds", "3")
        self.assertEqual(cli.returncode, 0, cli.stderr)
        note = next(l for l in cli.stderr.splitlines() if "local folds repaired" in l)
        self.assertIn(note[len("immerse: note: "):], found.notes)
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(surface, repair_folds=0.01)
        self.assertIn("not repaired within --repair-folds 0.01", str(e.exception))
        with self.assertRaises(immersion.InvalidInput):
            immersion.find_immersions(surface, repair_folds=-1.0)
        self.assertEqual(immersion.build_complex(surface, repair_folds=3.0).cells, 1)


class RealData(Fixture):
    """The paper's and third-party meshes from ../shared/data/real (skipped when absent)."""

    def real(self, name):
        path = os.path.join(SHARED, "3d", name)
        if not os.path.exists(path):
            self.skipTest(f"{path} not present")
        return path

    def test_local_folds_are_the_programs_verdict(self):
        path = self.real("cow.off")
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 3, cli.stderr)
        with self.assertRaises(immersion.NotImmersible) as e:
            immersion.find_immersions(immersion.read_surface(path))
        self.assertEqual(str(e.exception), cli_message(cli.stderr))
        self.assertIn("local fold", str(e.exception))

    def test_exact_contacts_are_resolved_like_the_program(self):
        path = self.real("doubleLoopWithCube.obj")
        found = immersion.find_immersions(immersion.read_surface(path))
        c = found.complex
        cli = run_immerse("immersions", path)
        self.assertEqual(cli.returncode, 0, cli.stderr)
        counts = f"{c.cells} cells, {c.patches} patches, {c.arcs} arcs"
        self.assertIn(counts, cli.stderr + cli.stdout)
        self.assertEqual(c.max_winding, 3)


if __name__ == "__main__":
    unittest.main()
