"""pandas DataFrames as data (issue 45: select and gap answered a DataFrame with a bare
KeyError: 0). A DataFrame's columns are the signals, named by their labels, exactly as the
same 2-D array with those names; a one-series function takes a one-column DataFrame and
refuses more, naming the functions that take them."""
import numpy as np
import pytest

import gmwm

pd = pytest.importorskip("pandas")

TRUTH = "WN(sigma2=1e-4)+RW(gamma2=1e-9)"


@pytest.fixture(scope="module")
def frame():
    x = gmwm.simulate(TRUTH, 2**14, freq=100, seed=3)
    y = gmwm.simulate(TRUTH, 2**14, freq=100, seed=4)
    return pd.DataFrame({"gyro_x": x, "gyro_y": y})


def test_select_takes_a_dataframes_columns_named_by_their_labels(frame):
    s = gmwm.select(frame, "WN+RW", freq=100)
    assert [c.name for c in s] == ["gyro_x", "gyro_y"]
    same = gmwm.select(frame.to_numpy(), "WN+RW", freq=100, names=["gyro_x", "gyro_y"])
    assert s.to_json() == same.to_json()


def test_gap_and_the_joint_selection_take_a_dataframes_columns(frame):
    g = gmwm.gap(frame, freq=100, model=TRUTH, replicates=40)
    assert [c.name for c in g.columns] == ["gyro_x", "gyro_y"]
    j = gmwm.select_joint([frame, frame * 1.1, frame * 0.9], "WN+RW", freq=100)
    assert [c.name for c in j.columns] == ["gyro_x", "gyro_y"]


def test_given_names_replace_the_labels_and_must_count_the_columns(frame):
    s = gmwm.select(frame, "WN+RW", freq=100, names=["a", "b"])
    assert [c.name for c in s] == ["a", "b"]
    with pytest.raises(gmwm.InputError, match="names: 1 names for 2 columns"):
        gmwm.select(frame, "WN+RW", freq=100, names=["a"])


def test_a_one_series_function_takes_a_one_column_dataframe_and_refuses_more(frame):
    # Named by its label, as the file's column would be (and a named Series by its name).
    one = gmwm.fit(frame[["gyro_x"]], "WN+RW", freq=100)
    assert one.name == "gyro_x" and gmwm.fit(frame["gyro_x"], "WN+RW", freq=100).to_json() == one.to_json()
    assert one.to_json() == gmwm.fit(frame["gyro_x"].to_numpy(), "WN+RW", freq=100, name="gyro_x").to_json()
    for call in (lambda: gmwm.fit(frame, "WN+RW", freq=100), lambda: gmwm.wv(frame, freq=100)):
        with pytest.raises(gmwm.InputError, match=r"data: found a DataFrame of 2 columns, expected one series "
                                                  r"\(e.g. data\['gyro_x'\]\); select, gap and the joint functions"):
            call()


def test_a_column_that_is_not_numbers_is_refused_by_its_label():
    bad = pd.DataFrame({"temp": ["warm"] * 100, "gyro_x": np.linspace(0.0, 1.0, 100)})
    with pytest.raises(gmwm.InputError, match="column 'temp': expected a 1-D array of numbers"):
        gmwm.select(bad, "WN", freq=100)
    with pytest.raises(gmwm.InputError, match="data: found a DataFrame with no column"):
        gmwm.select(pd.DataFrame(), "WN", freq=100)
