"""gmwm fleet on a Dask distributed cluster (issue 30, item 4): a LocalCluster of two worker
processes on loopback gives the table of the local run, bit for bit but the wall times, from
Python (scheduler=) and from the command line (--scheduler ADDRESS); a recording that fails on
a worker is a row with its reason; an address nobody answers is one line, exit 2."""
import json
import os

import pytest

import gmwm

distributed = pytest.importorskip("distributed", reason="python3-distributed is not installed")

from cli_support import run

TRUTH = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-4)+RW(gamma2=1e-10)"


@pytest.fixture(scope="module")
def fleet_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fleet_dask")
    rows = ["path,unit,model,units"]
    for k in range(1, 7):
        run(folder, "simulate", "--model", TRUTH, "--n", "16384", "--freq", "100", "--signals", "2", "--names",
            "gyro_x,gyro_y", "--seed", str(40 + k), "--output", f"u{k}.csv", "--quiet")
        rows.append(f'u{k}.csv,SN{k},IMU-X,"gyro=rad/s"')
    # One recording that only fails once read (a non-number deep in it): its row says why.
    text = (folder / "u6.csv").read_text().split("\n")
    text.insert(len(text) // 2, "0.5,abc,0.1")
    (folder / "u6.csv").write_text("\n".join(text))
    (folder / "fleet.csv").write_text("\n".join(rows) + "\n")
    return folder


@pytest.fixture(scope="module")
def cluster():
    # Two worker processes of one thread each on loopback, no dashboard.
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as c:
        yield c


def without_timings(doc):
    doc = json.loads(doc) if isinstance(doc, str) else doc
    doc.pop("run", None)
    for r in doc["rows"]:
        r.pop("seconds")
    return doc


def test_a_local_cluster_of_two_workers_gives_the_local_table_bit_for_bit(fleet_dir, cluster):
    manifest = str(fleet_dir / "fleet.csv")
    here = gmwm.fleet(manifest, model="2*AR1+WN+RW", cache=None)
    there = gmwm.fleet(manifest, model="2*AR1+WN+RW", cache=None, scheduler=cluster)
    assert without_timings(there.to_json()) == without_timings(here.to_json())
    assert there.failed == 1
    failed = [r for r in there.rows if r.status != "ok"]
    assert len(failed) == 1 and failed[0].unit == "SN6" and "abc" in failed[0].status
    assert sum(r.status == "ok" for r in there.rows) == 10


def test_the_command_line_with_scheduler_gives_the_local_table_and_caches_what_the_workers_did(fleet_dir, cluster):
    run(fleet_dir, "fleet", "fleet.csv", "--model", "AR1+WN+RW", "--no-cache", "--json", "local.json", "--quiet")
    run(fleet_dir, "fleet", "fleet.csv", "--model", "AR1+WN+RW", "--cache", "dask-cache", "--scheduler",
        cluster.scheduler_address, "--json", "dask.json", "--quiet")
    local = without_timings((fleet_dir / "local.json").read_text())
    remote = without_timings((fleet_dir / "dask.json").read_text())
    for d in (local, remote):
        d.pop("cache")
    assert remote == local
    # The five recordings the workers analysed are cached here: a local re-run takes them.
    entries = [p for p in os.listdir(fleet_dir / "dask-cache") if p.endswith(".json")]
    assert len(entries) == 5
    run(fleet_dir, "fleet", "fleet.csv", "--model", "AR1+WN+RW", "--cache", "dask-cache", "--json", "again.json",
        "--quiet")
    assert json.loads((fleet_dir / "again.json").read_text())["cached"] == 5


def test_a_scheduler_nobody_answers_is_one_line_and_exit_2(fleet_dir):
    done = run(fleet_dir, "fleet", "fleet.csv", "--model", "WN+RW", "--no-cache", "--scheduler",
               "tcp://127.0.0.1:9", "--json", "never.json", check=False)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("gmwm: error: --scheduler tcp://127.0.0.1:9: "), done.stderr
    assert "cannot reach the Dask scheduler" in lines[0]
    assert not (fleet_dir / "never.json").exists()


def test_a_scheduler_address_that_is_not_one_is_refused_before_any_work(fleet_dir):
    done = run(fleet_dir, "fleet", "fleet.csv", "--model", "WN+RW", "--scheduler", "tcp://host;rm -rf /", check=False)
    assert done.returncode == 2
    assert done.stderr.startswith("gmwm: error: --scheduler: found 'tcp://host;rm -rf /', expected a Dask")


def test_a_worker_that_cannot_run_gmwm_ends_the_run_saying_so_instead_of_failing_every_row(fleet_dir, cluster):
    with distributed.Client(cluster) as client:
        # Every worker loses the gmwm module (as a worker set up without it would be).
        client.run(lambda: __import__("sys").modules.__setitem__("gmwm", None))
        try:
            with pytest.raises(Exception, match="a worker could not run recording .* needs the gmwm Python module"):
                gmwm.fleet(str(fleet_dir / "fleet.csv"), model="WN+RW", cache=None, scheduler=client)
        finally:
            client.run(lambda: __import__("sys").modules.pop("gmwm", None))
