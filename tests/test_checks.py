"""The declared argument contracts (idkit.checks): the specs themselves, and every declared argument
of every public function fed the values its spec must refuse, as one table."""

import importlib
import math
import pkgutil

import numpy as np
import pytest

import idkit
from idkit.checks import DECLARED, Choice, Either, Flag, Items, Real, Samples, Seed, Whole, accepts
from idkit.errors import DataError, ParameterError

for _module in pkgutil.walk_packages(idkit.__path__, "idkit."):
    if not _module.name.endswith("__main__"):
        importlib.import_module(_module.name)

ARGUMENTS = [pytest.param(contract, name, spec, id=f"{contract.name}-{name}")
             for contract in DECLARED for name, spec in contract.specs.items()]


def test_some_public_functions_declare_their_arguments():
    assert len(ARGUMENTS) > 50


@pytest.mark.parametrize(("contract", "name", "spec"), ARGUMENTS)
def test_every_declared_argument_refuses_its_bad_values_naming_itself(contract, name, spec):
    """Only the bad argument is given: the contract is checked before the call binds the others,
    so the refusal names the argument whatever the function needs besides."""
    for bad in spec.bad_values():
        with pytest.raises(contract.error, match=rf"^{name}(\[\d+\])*: found .*, expected "):  # an item: name[i]
            contract.function(**{name: bad})


def test_real_coerces_and_states_its_bounds_in_one_template():
    spec = Real(unit="Hz", gt=0, le=100)
    assert spec.check(np.float32(2.5), "freq") == 2.5 and type(spec.check(3, "freq")) is float
    with pytest.raises(ParameterError, match=r"^freq: found 0, expected a finite real number > 0 and <= 100 Hz$"):
        spec.check(0, "freq")
    with pytest.raises(ParameterError, match=r"^freq: found nan, expected"):
        spec.check(math.nan, "freq")
    assert Real(optional=True).check(None, "x") is None
    assert Real(unit="m").expected() == "a finite real number in m"  # a unit without bounds reads "in"


def test_whole_never_truncates_and_reads_exponent_notation():
    spec = Whole(ge=1, le=10**6)
    assert spec.check(1e3, "count") == 1000 and type(spec.check(np.int64(4), "count")) is int
    for bad in (2.5, True, "3", 0, 10**6 + 1):
        with pytest.raises(ParameterError, match="^count: found"):
            spec.check(bad, "count")
    assert spec.parse("1e6") == 10**6
    with pytest.raises(ValueError, match="expected a whole number from 1 to 1000000"):
        spec.parse("2.5")


def test_samples_returns_a_read_only_view_and_never_alters_the_callers_array():
    record = np.arange(5.0)
    checked = Samples(min_size=3).check(record, "force")
    assert np.shares_memory(checked, record) and not checked.flags.writeable and record.flags.writeable
    assert Samples().check([1, 2], "x").dtype == np.float64
    with pytest.raises(DataError, match=r"^x: found inf at index 1, expected a 1-D array"):
        Samples().check([1.0, np.inf], "x", DataError)
    with pytest.raises(DataError, match=r"^x: found nan at index \(1, 0\), expected a 1-D or 2-D array"):
        Samples(ndim=(1, 2)).check([[1.0, 2.0], [np.nan, 3.0]], "x", DataError)


def test_items_names_the_position_of_a_refused_item():
    spec = Items(Real(unit="m", gt=0), min_size=1)
    assert spec.check([1, np.float32(2.0)], "heights") == (1.0, 2.0)
    for bad, message in (([1.0, -2.0], r"^heights\[1\]: found -2, expected a finite real number > 0 m$"),
                         ([], r"^heights: found 0 items, expected a sequence of at least 1 item, each"),
                         ("ab", r"^heights: found str, expected a sequence")):
        with pytest.raises(ParameterError, match=message):
            spec.check(bad, "heights")
    either = Either((Choice(("all",)), spec))  # a sequence refused for one item names that item
    with pytest.raises(ParameterError, match=r"^heights\[0\]: found 'a', expected a finite real number"):
        either.check(["a"], "heights")
    with pytest.raises(ParameterError, match=r"^heights: found 3.0, expected one of 'all' or a sequence"):
        either.check(3.0, "heights")


def test_choice_flag_and_seed():
    assert Choice(("linear", "rest")).check("rest", "start") == "rest"
    assert Flag().check(np.True_, "shooting") is True
    assert Seed().check(np.int64(7), "seed") == 7
    generator = np.random.default_rng(0)
    assert Seed().check(generator, "seed") is generator
    for spec, bad in ((Choice(("a",)), "b"), (Flag(), 1), (Seed(), 2**32)):
        with pytest.raises(ParameterError, match="^x: found"):
            spec.check(bad, "x")


def test_accepts_refuses_a_declaration_of_an_argument_the_function_lacks():
    with pytest.raises(TypeError, match="no argument"):
        @accepts(missing=Real())
        def function(present):
            return present


def test_defaults_are_trusted_and_given_values_reach_the_body_coerced():
    @accepts(count=Whole(ge=1), error=DataError)
    def repeat(text, *, count=2):
        return text * count

    assert repeat("ab") == "abab" and repeat("ab", count=3.0) == "ababab"


def test_either_takes_the_first_spec_that_accepts_and_names_both_expectations():
    spec = Either((Whole(ge=1), Choice(("auto",))))
    assert spec.check("auto", "order") == "auto" and spec.check(3.0, "order") == 3
    with pytest.raises(ParameterError, match=r"^order: found 0, expected a whole number >= 1 or one of 'auto'$"):
        spec.check(0, "order")
    assert "auto" not in spec.bad_values() and 2.5 in spec.bad_values() and None in spec.bad_values()
