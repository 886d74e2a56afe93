"""Inventories: CSV and TOML formats, frames, sliding warnings and row-numbered errors."""

import math
import warnings

import pytest

from rocking.assessment.inventory import DEFAULT_E, read_inventory
from rocking.dynamics.body import Block
from rocking.errors import InputError
from rocking.structures.frames import ShearFrame


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_csv_inventory(tmp_path):
    path = write(
        tmp_path,
        "inv.csv",
        (
            "# a comment line\n"
            "Name,Height [m],Width [m],R,gamma,Location,Frame,e,mu,notes\n"
            "rack,2.0,0.5,,,floor 3,paper-2.0,,0.5,anything\n"
            "statue,,,1.22,4,ground,,housner,,\n"
            "\n"
            "tank,3.0,1.5,,,floor 5,,0.9,,\n"
        ),
    )
    inv = read_inventory(path, frame="paper-0.5")
    rack, statue, tank = inv
    assert rack.block == Block.from_dimensions(2.0, 0.5)
    assert (rack.floor, rack.frame, rack.location) == (
        3,
        ShearFrame.preset("paper-2.0"),
        "floor 3 of paper-2.0",
    )
    assert rack.e == DEFAULT_E and rack.mu == 0.5 and rack.mu_k is None
    assert statue.block == Block(1.22, 4.0) and statue.location == "ground"
    # Housner (1963): e = 1 − 1.5·sin²α with tan α = 1/4 -> sin²α = 1/17
    assert statue.e == pytest.approx(1 - 1.5 / 17, rel=1e-12)
    assert tank.frame.name == "paper-0.5" and tank.e == 0.9  # the default frame fills in
    assert "row 6" in tank.source  # spreadsheet numbering: comment line 1, header row 2


def test_toml_inventory_with_its_own_frame(tmp_path):
    path = write(
        tmp_path,
        "inv.toml",
        """
frame = "lab"

[frames.lab]
weights_kN_per_g = [444.82, 444.82, 444.82]
stiffness_kN_per_cm = [55.23, 55.23, 55.23]

[[items]]
name = "freezer"
height = 2.0
width = 0.75
location = "floor 3"
mu = 0.6

[[items]]
name = "cabinet"
R = 1.0
gamma = 3.0
location = "floor 1"
frame = "paper-1.0"
""",
    )
    freezer, cabinet = read_inventory(path)
    assert freezer.frame == ShearFrame.from_paper_units([444.82] * 3, [55.23] * 3, name="lab")
    assert freezer.location == "floor 3 of lab"
    assert cabinet.frame.name == "paper-1.0" and cabinet.block == Block(1.0, 3.0)


def test_frame_toml_file_relative_to_the_inventory(tmp_path):
    write(tmp_path, "bldg.toml", "masses_kg = [1e5, 1e5]\nstiffnesses_N_per_m = [4e7, 4e7]\n")
    path = write(
        tmp_path, "inv.csv", "name,height,width,location,frame\nx,1,0.4,floor 2,bldg.toml\n"
    )
    (item,) = read_inventory(path)
    assert item.frame.masses == (1e5, 1e5) and item.location == "floor 2 of bldg"


def test_friction_columns_mu_and_mu_k(tmp_path):
    # Issue 45: mu is the static coefficient (empty: infinite friction, the rocking model),
    # mu_k the kinetic one (empty: mu_k = mu). A low mu is no longer a warning: the screening
    # models the sliding (the old "mu <= B/H: may slide" flag and its SlidingWarning are gone).
    path = write(
        tmp_path,
        "inv.csv",
        "name,height,width,location,mu,mu_k\n"
        "a,2.0,0.5,ground,0.2,0.15\nb,2.0,0.5,ground,0.3,\nc,2.0,0.5,ground,,\n",
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inv = read_inventory(path)
    assert [(it.mu, it.mu_k) for it in inv] == [(0.2, 0.15), (0.3, None), (None, None)]


@pytest.mark.parametrize(
    "row, message",
    [
        ("a,2.0,0.5,ground,,0.2", "mu_k needs mu"),
        ("a,2.0,0.5,ground,0.2,0.3", "mu_k = 0.3 exceeds mu = 0.2"),
        ("a,2.0,0.5,ground,0.2,-1", "mu_k"),
    ],
)
def test_bad_kinetic_friction_is_refused_naming_the_row(tmp_path, row, message):
    path = write(tmp_path, "inv.csv", f"name,height,width,location,mu,mu_k\n{row}\n")
    with pytest.raises(InputError, match=rf"row 2: item 'a': .*{message}"):
        read_inventory(path)


def test_every_malformed_row_is_reported_with_its_row_number(tmp_path):
    path = write(
        tmp_path,
        "bad.csv",
        (
            "name,height,width,location,frame,e,mu\n"  # row 1
            "ok,2.0,0.5,ground,,,\n"  # row 2
            "missing,2.0,,ground,,,\n"  # row 3: missing width
            "texty,tall,0.5,ground,,,\n"  # row 4: text for a number
            "flat,2.0,-0.5,ground,,,\n"  # row 5: non-positive size
            "high,2.0,0.5,floor 9,paper-2.0,,\n"  # row 6: no floor 9 in a 5-story frame
            "where,2.0,0.5,floor 1,nosuchframe,,\n"  # row 7: unknown frame
            "nowhere,2.0,0.5,attic,,,\n"  # row 8: bad location
            "orphan,2.0,0.5,floor 2,,,\n"  # row 9: floor without a frame
            "bounce,2.0,0.5,ground,,1.5,\n"  # row 10: e out of (0, 1]
            "ok,1.0,0.5,ground,,,\n"  # row 11: repeated name
            ",1.0,0.5,ground,,,\n"
        ),
    )  # row 12: no name
    with pytest.raises(InputError) as info:
        read_inventory(path)
    msg = str(info.value)
    assert msg.startswith(f"10 malformed items in {path}")
    # (row 10: the message of the one restitution parser, shared with simulate and the CLI)
    expected = {
        3: "missing width",
        4: "height must be a number",
        5: "width must be",
        6: "unknown floor 9",
        7: "unknown frame 'nosuchframe'",
        8: "location must be",
        9: "needs a frame",
        10: "e must be a number in (0, 1]",
        11: "repeats that of row 2",
        12: "missing name",
    }
    for row, words in expected.items():
        line = next(li for li in msg.splitlines() if li.startswith(f"row {row}:"))
        assert words in line, line
    assert "row 2:" not in msg
    assert msg.count(str(path)) == 1  # the file named once, each row by its number
    assert msg.endswith("give a default frame (--frame NAME on the command line, frame= in Python)")


def test_toml_item_errors_name_the_item(tmp_path):
    path = write(
        tmp_path,
        "inv.toml",
        '[[items]]\nname = "a"\nheight = 2\nwidth = 0.5\n'
        'location = "ground"\ncolour = "red"\n\n[[items]]\nname = "b"\nR = 1\n'
        'location = "ground"\n',
    )
    with pytest.raises(
        InputError,
        match=r"item 1: unknown key\(s\) colour(.|\n)*"
        r"item 2: item 'b': missing gamma",
    ):
        read_inventory(path)


def test_file_level_errors(tmp_path):
    with pytest.raises(InputError, match="header must name"):
        read_inventory(write(tmp_path, "h.csv", "a,b,c\n1,2,3\n"))
    with pytest.raises(InputError, match="no items"):
        read_inventory(write(tmp_path, "e.csv", "name,height,width,location\n"))
    with pytest.raises(InputError, match="not valid TOML"):
        read_inventory(write(tmp_path, "t.toml", "items = [\n"))
    with pytest.raises(InputError, match=r"\[frames.x\]: give either"):
        read_inventory(
            write(
                tmp_path,
                "f.toml",
                "[frames.x]\nmasses_kg = [1.0]\n"
                "[[items]]\nname='a'\nR=1\ngamma=2\nlocation='ground'\n",
            )
        )


def test_shipped_example_inventory_reads():
    from importlib.resources import files

    inv = read_inventory(files("rocking") / "data" / "example_inventory.csv", frame="paper-2.0")
    assert len(inv) == 16
    assert {it.floor for it in inv} == {0, 1, 2, 3, 4, 5}
    assert all(math.isfinite(it.block.R) for it in inv)
