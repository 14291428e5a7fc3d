"""Parameter validation, declarations and the JSON model file."""

import json
import math
import re

import numpy as np
import pytest

from idkit.errors import ModelFileError, ParameterError
from idkit.models import (
    BoucWenModel,
    ClearanceIwanModel,
    CoulombSpringSystem,
    GeneralizedMaxwell,
    HybridSystem,
    IwanModel,
    ModulatedIwanModel,
    PinchedBoucWenModel,
    RateDependentIwanModel,
    SDOFSystem,
    VoigtModel,
    library,
    load_model,
    save_model,
)

GOOD_IWAN = dict(g1=3e3, k=[3e3, 3e3], fc=[8.3, 14.6])
GOOD_BOUCWEN = dict(k1=3e4, k2=1e6, k3=0.0, alpha=1e5, beta=8e4, gamma=2e4, n=2)


@pytest.mark.parametrize(
    "factory, kwargs, fragment",
    [
        (IwanModel, {**GOOD_IWAN, "g1": -1.0}, "'g1'"),
        (IwanModel, {**GOOD_IWAN, "k": [3e3, -5.0]}, "'k_2'"),
        (IwanModel, {**GOOD_IWAN, "fc": [8.3, 0.0]}, "'fc_2'"),
        (IwanModel, {**GOOD_IWAN, "fc": [8.3]}, "found 1 values, expected 2"),
        (IwanModel, {**GOOD_IWAN, "k": []}, "expected at least 1"),
        (IwanModel, {**GOOD_IWAN, "g3": math.nan}, "'g3'"),
        (IwanModel, {**GOOD_IWAN, "c_visc": -0.1}, "'c_visc'"),
        (GeneralizedMaxwell, dict(k0=1e3, k=[1e3], rate=[-2.0]), "'rate_1'"),
        (GeneralizedMaxwell, dict(k0=-1.0, k=[1e3], rate=[2.0]), "'k0'"),
        (GeneralizedMaxwell, dict(k0=1e3, k=[1e3, 2e3], rate=[2.0]), "found 1 values, expected 2"),
        (GeneralizedMaxwell, dict(k0=1e3, k=[1e3], rate=[2.0], m_eff=-0.1), "'m_eff'"),
        (VoigtModel, dict(k=math.inf, damping=1.0), "'k'"),
        (VoigtModel, dict(k=1.0, damping="abc"), "'damping'"),
        (BoucWenModel, dict(k1=1.0, k2=0, k3=0, alpha=-1.0, beta=1.0, gamma=1.0, n=1.0), "'alpha'"),
        (BoucWenModel, dict(k1=1.0, k2=0, k3=0, alpha=1.0, beta=-2.0, gamma=1.0, n=1.0), "beta + gamma"),
        (BoucWenModel, dict(k1=1.0, k2=0, k3=0, alpha=1.0, beta=1.0, gamma=1.0, n=0.0), "'n'"),
        (SDOFSystem, dict(mass=-2.0, isolator=VoigtModel(k=1.0, damping=1.0)), "'mass'"),
        (SDOFSystem, dict(mass=2.0, isolator="rubber"), "expected an idkit isolator model"),
        (CoulombSpringSystem, dict(mass=10.0, stiffness=9e3, friction_force=-1.0), "'friction_force'"),
        # booleans and text are not numbers: float(True) is 1 kg, float("8") is 8 kg (a model file refuses both)
        (SDOFSystem, dict(mass=True, isolator=VoigtModel(k=1.0, damping=1.0)), "found True (bool)"),
        (SDOFSystem, dict(mass=np.True_, isolator=VoigtModel(k=1.0, damping=1.0)), "'mass': found"),
        (VoigtModel, dict(k="1e4", damping=1.0), "'k': found '1e4', expected a finite real number"),
        (IwanModel, {**GOOD_IWAN, "k": [3e3, True]}, "'k': found [3000.0, True]"),
        (IwanModel, {**GOOD_IWAN, "fc": np.array(["8.3", "14.6"])}, "'fc': found"),
        (GeneralizedMaxwell, dict(k0=1e3, k=[1e3], rate=np.array([True])), "'rate': found"),
    ],
)
def test_invalid_parameters_raise_named_errors(factory, kwargs, fragment):
    with pytest.raises(ParameterError) as caught:
        factory(**kwargs)
    assert fragment in str(caught.value)
    assert isinstance(caught.value, ValueError)


def test_declarations_drive_vectors():
    model = library.get("table_7_1_wire_rope")
    names = [spec.name for spec in model.param_specs()]
    assert names == ["g1", "g2", "g3", "k_1", "k_2", "fc_1", "fc_2", "c_visc"]
    assert list(model.params()) == names
    assert model.with_vector(model.to_vector()) == model
    with pytest.raises(ParameterError, match="shape"):
        model.with_vector([1.0, 2.0])
    assert "g2=2.45e+05 N/m^2" in repr(model)


@pytest.mark.parametrize("name", library.names())
def test_model_file_round_trip(tmp_path, name):
    model = library.get(name)
    path = save_model(model, tmp_path / f"{name}.json", provenance={"source": "library", "seed": 1})
    loaded = load_model(path)
    assert loaded.to_dict() == model.to_dict()
    document = json.loads(path.read_text())
    assert document["format"] == "idkit-model" and document["provenance"]["seed"] == 1
    with pytest.raises(FileExistsError):
        save_model(model, path)


def test_coulomb_spring_round_trip(tmp_path):
    system = CoulombSpringSystem(10.0, 9000.0, 1000.0, damping=10.0)
    assert load_model(save_model(system, tmp_path / "cs.json")) == system


@pytest.mark.parametrize(
    "mutate, fragment",
    [
        (lambda d: d.update(format="other"), "expected 'idkit-model'"),
        (lambda d: d.update(format_version=99), "format_version"),
        (lambda d: d["model"].update(kind="spring"), "expected one of"),
        (lambda d: d["model"]["params"].pop("g1"), "'g1' missing"),
        (lambda d: d["model"]["params"].update(k_1=-3.0), "'k_1'"),
        (lambda d: d["model"]["units"].update(g1="N/mm"), "units.g1"),
        (lambda d: d["model"]["params"].update(bogus=1.0), "unknown parameters"),
    ],
)
def test_bad_model_files_raise(tmp_path, mutate, fragment):
    path = save_model(library.get("table_a1_asymmetric"), tmp_path / "model.json")
    document = json.loads(path.read_text())
    mutate(document)
    path.write_text(json.dumps(document))
    with pytest.raises(ModelFileError, match=fragment.replace("(", r"\(")):
        load_model(path)


def test_hybrid_small_amplitude_transmissibility_is_series_of_parts():
    system = library.get("hybrid_asymmetric")
    freq = np.array([0.01])
    assert abs(system.transmissibility(freq)[0]) == pytest.approx(1.0, rel=1e-4)
    stiff = system.series_stiffness(freq)[0]
    k_wr = library.get("table_a1_asymmetric").stuck_stiffness
    k_el = library.get("table_b1_medium").complex_stiffness(0.01)
    assert stiff == pytest.approx(1 / (1 / k_wr + 1 / k_el), rel=1e-6)
    assert isinstance(system, HybridSystem)


_FREQ_CALLS = {
    "maxwell complex_stiffness": lambda f: library.get("table_7_3_elastomer").complex_stiffness(f),
    "maxwell loss_factor": lambda f: library.get("table_b1_medium").loss_factor(f),
    "voigt complex_stiffness": lambda f: VoigtModel(k=1e4, damping=20.0).complex_stiffness(f),
    "voigt damping_ratio": lambda f: VoigtModel(k=1e4, damping=20.0).damping_ratio(f),
    "iwan small_amplitude_stiffness": lambda f: IwanModel(**GOOD_IWAN).small_amplitude_stiffness(f),
    "boucwen small_amplitude_stiffness": lambda f: BoucWenModel(**GOOD_BOUCWEN).small_amplitude_stiffness(f),
    "sdof transmissibility": lambda f: library.get("system_a1_symmetric").transmissibility(f),
    "hybrid transmissibility": lambda f: library.get("hybrid_asymmetric").transmissibility(f),
    "hybrid series_stiffness": lambda f: library.get("hybrid_asymmetric").series_stiffness(f),
}


@pytest.mark.parametrize("call", _FREQ_CALLS.values(), ids=_FREQ_CALLS.keys())
@pytest.mark.parametrize("freq, found", [
    ([1.0, math.inf], "found inf"), (-math.inf, "found -inf"), (1e308, "found 1e+308"), (1j, "found 1j"),
])
def test_model_frequencies_that_are_no_finite_number_are_refused_naming_freq(call, freq, found):
    """Through every method that reaches a declared frequency (idkit.models.base.FREQUENCY; NaN, text
    and booleans are in the declared table): no numpy warning, the refusal names ``freq``. 1e308 Hz
    would overflow 2 pi f."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ParameterError, match=re.escape(f"freq: {found}")) as raised:
            call(freq)
    assert "expected" in str(raised.value) and "Hz" in str(raised.value)


def test_model_frequencies_accept_finite_numbers_and_arrays():
    elastomer = library.get("table_7_3_elastomer")
    np.testing.assert_array_equal(elastomer.complex_stiffness([1, 2.5]),
                                  elastomer.complex_stiffness(np.array([1.0, 2.5])))
    assert abs(library.get("system_a1_symmetric").transmissibility(0.0)) == pytest.approx(1.0)


_IWAN = dict(g1=1e4, g2=1e5, g3=1e8, k=[1e4, 2e4], fc=[1.0, 3.0], c_visc=2.0)
_BOUC_WEN = dict(k1=1e3, k2=0.0, k3=0.0, alpha=5e3, beta=2e3, gamma=1e3, n=1.0)
#: every isolator model from a parameter mapping, with the names its from_params may do without
FROM_PARAMS_MODELS = [
    (IwanModel(**_IWAN), {"g2", "g3", "c_visc"}),
    (GeneralizedMaxwell(k0=1e4, k=[1e3, 2e3], rate=[10.0, 100.0], m_eff=0.1), {"m_eff"}),
    (VoigtModel(k=1e4, damping=5.0), {"m_eff"}),
    (BoucWenModel(**_BOUC_WEN), {"b", "c", "c_visc"}),
    (PinchedBoucWenModel(**_BOUC_WEN, pinch=0.8, pinch_width=0.2), {"b", "c", "c_visc", "pinch_shift"}),
    (ModulatedIwanModel.from_iwan(IwanModel(**_IWAN), slip_modulation=0.3, slip_length=2e-3),
     {"g2", "g3", "c_visc", "slip_growth"}),
    (RateDependentIwanModel(**_IWAN, slip_rate_gain=0.2, slip_speed=0.01), {"g2", "g3", "c_visc"}),
    (ClearanceIwanModel(gap=1e-4, **_IWAN), {"g2", "g3", "c_visc"}),
]


@pytest.mark.parametrize("model, optional", FROM_PARAMS_MODELS, ids=lambda value: type(value).__name__)
def test_from_params_round_trips_and_names_a_missing_or_unknown_parameter(model, optional):
    params = model.params()
    assert type(model).from_params(params) == model
    for name in params:
        others = {key: value for key, value in params.items() if key != name}
        if name in optional:
            type(model).from_params(others)  # a default stands in
        elif not re.fullmatch(r"(k|fc|rate)_\d", name):  # an element's value: the element count says it
            with pytest.raises(ParameterError, match=rf": parameter '{name}' missing"):
                type(model).from_params(others)
        else:
            with pytest.raises(ParameterError):
                type(model).from_params(others)
    with pytest.raises(ParameterError, match=r"unknown parameters \['bogus'\]"):
        type(model).from_params({**params, "bogus": 1.0})
