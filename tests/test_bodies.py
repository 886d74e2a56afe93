"""Bodies files: the two ways to give a size, names, and an error naming the file and the row for
every malformed input."""

import math

import pytest

import rocking
from rocking.assessment.bodies import NamedBody, read_bodies, read_bodies_table
from rocking.dynamics.body import Block, BodyWarning, G
from rocking.errors import InputError


def _write(tmp_path, text, name="bodies.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_r_gamma_columns_with_names_comments_and_units(tmp_path):
    path = _write(tmp_path, "# two cabinets\nName, R [m], gamma\ncab A,1.22,4\n\ncab B,2.44,2.5\n")
    assert read_bodies_table(path) == [
        NamedBody("cab A", Block(1.22, 4.0)),
        NamedBody("cab B", Block(2.44, 2.5)),
    ]
    assert read_bodies(path) == [Block(1.22, 4.0), Block(2.44, 2.5)]


def test_h_b_columns_give_r_and_gamma(tmp_path):
    # H = 3, B = 4: R = ½·sqrt(9 + 16) = 2.5 m, γ = 0.75 (a squat body is legal, with a warning
    # that H and B may have been swapped).
    path = _write(tmp_path, "H,B\n3,4\n")
    with pytest.warns(BodyWarning, match="swapped"):
        (body,) = read_bodies_table(path)
    assert pytest.approx(2.5, rel=1e-15) == body.block.R
    assert body.block.gamma == pytest.approx(0.75, rel=1e-15)
    assert body.name == body.block.label  # no name column: the Block label


def test_paper_body_from_dimensions_round_trips(tmp_path):
    b = Block(1.2192, 4.0)
    path = _write(tmp_path, f"B,H\n{b.B!r},{b.H!r}\n")
    (got,) = read_bodies(path)
    assert math.isclose(got.R, b.R, rel_tol=1e-14) and math.isclose(got.gamma, 4.0, rel_tol=1e-14)


@pytest.mark.parametrize(
    "text, where, problem",
    [
        ("", "", "empty bodies file"),
        ("# only a comment\n\n", "", "empty bodies file"),
        ("R,gamma\n", "", r"no bodies below the header \(line 1\)"),
        ("R,H\n1,2\n", "line 1", "missing column"),
        ("name,R\na,1\n", "line 1", "missing column"),
        ("R,gamma,H\n1,2,3\n", "line 1", "not a mix"),
        ("R,gama\n1,2\n", "line 1", "unknown column 'gama'"),
        ("R,gamma,R\n1,2,3\n", "line 1", "appears twice"),
        ("R,gamma\n1,2\n1.5,four\n", r"row 2 \(line 3\)", "gamma must be a number .* 'four'"),
        ("R,gamma\n1,2\n\n-1.5,4\n", r"row 2 \(line 4\)", r"R must be a finite number > 0 \[m\]"),
        ("H,B\n2,0\n", r"row 1 \(line 2\)", r"B must be a finite number > 0 \[m\], got 0"),
        ("R,gamma\nnan,3\n", r"row 1 \(line 2\)", "R must be a finite number"),
        ("R,gamma\n1,\n", r"row 1 \(line 2\)", "an empty cell"),
        ("R,gamma\n1,2\n3\n", r"row 2 \(line 3\)", "1 value"),
        ("name,R,gamma\na,1,2\na,2,3\n", r"row 2 \(line 3\)", "repeats that of row 1"),
    ],
)
def test_errors_name_file_row_and_problem(tmp_path, text, where, problem):
    path = _write(tmp_path, text)
    with pytest.raises(InputError, match=f"bodies.csv: {where}.*{problem}"):
        read_bodies(path)


def test_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="nope.csv: cannot read"):
        read_bodies(tmp_path / "nope.csv")


def test_general_bodies_from_mass_properties(tmp_path):
    # A cabinet whose mass sits low: h_cg = 0.6 m, b = 0.3 m, r_g = 0.5 m; p² = g·R/(r_g² + R²)
    # with R = sqrt(h_cg² + b²) (rigid body about the pivot, parallel-axis theorem)
    path = _write(tmp_path, "name,h_cg [m],b [m],r_g [m]\ncabinet,0.6,0.3,0.5\n")
    (body,) = read_bodies_table(path)
    R = math.hypot(0.6, 0.3)
    assert math.isclose(body.block.R, R, rel_tol=1e-15)
    assert math.isclose(body.block.gamma, 2.0, rel_tol=1e-15)
    assert math.isclose(body.block.p_squared(), G * R / (0.25 + R**2), rel_tol=1e-14)
    with pytest.raises(InputError, match="missing column"):
        read_bodies(_write(tmp_path, "h_cg,b\n0.6,0.3\n"))
    with pytest.raises(InputError, match="not a mix"):
        read_bodies(_write(tmp_path, "h_cg,b,r_g,R\n0.6,0.3,0.5,1\n"))
    inventory = tmp_path / "inv.csv"
    inventory.write_text(
        "name,h_cg,b,r_g,location\ncabinet,0.6,0.3,0.5,ground\nrack,1,0.2,,ground\n"
    )
    with pytest.raises(InputError, match="rack.*r_g"):
        rocking.read_inventory(inventory)
    inventory.write_text("name,h_cg,b,r_g,location\ncabinet,0.6,0.3,0.5,ground\n")
    (item,) = rocking.read_inventory(inventory)
    assert item.block == body.block
