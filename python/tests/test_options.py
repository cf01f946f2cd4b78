"""Numbers at the edge of their types (issue 25): an alpha so small that the level
1 - alpha/2 rounds to 1 is refused with the valid range, not an overflow inside Boost."""
import pytest

import gmwm


@pytest.mark.parametrize("call", [
    lambda x: gmwm.wv(x, freq=1.0, alpha=1e-320),
    lambda x: gmwm.fit(x, "WN", freq=1.0, alpha=1e-320),
    lambda x: gmwm.select(x, "WN+RW", freq=1.0, alpha=1e-17),
])
def test_a_subnormal_alpha_is_refused_with_the_valid_range(call):
    x = gmwm.simulate("WN(sigma2=1)", 4096)
    with pytest.raises(gmwm.InputError, match="alpha must be at least 1e-10"):
        call(x)


@pytest.mark.parametrize("call, field", [
    (lambda x: gmwm.fit(x, "WN", freq=100, units="furlong"), "units 'furlong'"),
    (lambda x: gmwm.allan(x, freq=100, units="gyro=furlong"), "units 'gyro=furlong'"),
    (lambda x: gmwm.select(x, "WN+RW", freq=100, units="parsec"), "units 'parsec'"),
])
def test_a_refusal_names_the_keyword_argument_not_the_command_lines_option(call, field):
    # One table of options and fields for every face (issue 45): Python said "--units".
    x = gmwm.simulate("WN(sigma2=1)", 4096)
    with pytest.raises(gmwm.InputError) as e:
        call(x)
    assert str(e.value).startswith(field), str(e.value)
    assert "--" not in str(e.value), str(e.value)


def test_select_ranks_listed_models_as_the_cli_does_and_refuses_a_bad_list_in_its_words(tmp_path):
    # The ';' list was the CLI's alone (issue 45); one rule now (pipeline::set_select_models).
    import json
    import subprocess

    from cli_support import CLI
    x = gmwm.simulate("WN(sigma2=1e-4)+RW(gamma2=1e-9)", 2**14, freq=100, seed=5)
    path = tmp_path / "x.csv"
    path.write_text("gyro_x\n" + "\n".join(repr(float(v)) for v in x) + "\n")
    cli = subprocess.run([CLI, "select", str(path), "--freq", "100", "--models", "WN+RW;AR1+WN;WN", "--json", "-",
                          "--quiet"], capture_output=True, text=True, check=True)
    mine = gmwm.select(x, models="WN+RW;AR1+WN;WN", freq=100, names=["gyro_x"])
    assert json.loads(mine.to_json()) == json.loads(cli.stdout)["columns"]
    bad = subprocess.run([CLI, "select", str(path), "--freq", "100", "--models", "WN;;RW"], capture_output=True,
                         text=True)
    assert bad.stderr.strip().endswith('--models "WN;;RW": empty model in the list')
    with pytest.raises(gmwm.InputError, match='^models "WN;;RW": empty model in the list$'):
        gmwm.select(x, models="WN;;RW", freq=100)
    with pytest.raises(gmwm.InputError, match="^select: give either model SPEC"):
        gmwm.select(x, "WN", models="WN;RW", freq=100)
