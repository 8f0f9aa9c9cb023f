"""The workflow on a real one-node Slurm (Debian's slurm-wlm + munge), through the Slurm profile.

The fixture starts munged, slurmctld and slurmd without systemd, writes
/etc/slurm/slurm.conf (job steps read the default path: the plugin clears SLURM_*
variables inside jobs), runs a tiny config with ``profiles/slurm``, and stops
every daemon it started by PID. It skips, saying why, where Slurm is not installed, the tests do not
run as root, or a Slurm is already configured; a Slurm that starts but never comes up fails.
"""

import os
import shutil
import socket
import subprocess
import time
from pathlib import Path

import pytest
from test_workflow import SNAKEFILE, SNAKEMAKE, tiny_config, yaml

from heatdata.io.tables import read_table

pytestmark = pytest.mark.workflow  # every test here runs snakemake

ROOT = Path(__file__).resolve().parents[2]
SLURM_CONF = Path("/etc/slurm/slurm.conf")
BINARIES = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo")


def slurm_conf(state: Path) -> str:
    host = socket.gethostname().split(".")[0]
    return "\n".join(
        [
            "# written by heatdata's tests/test_slurm.py; removed when the test ends",
            "ClusterName=heatdata",
            f"SlurmctldHost={host}(127.0.0.1)",
            "SlurmUser=root",
            "AuthType=auth/munge",
            f"StateSaveLocation={state}/state",
            f"SlurmdSpoolDir={state}/spool",
            f"SlurmctldPidFile={state}/slurmctld.pid",
            f"SlurmdPidFile={state}/slurmd.pid",
            f"SlurmctldLogFile={state}/slurmctld.log",
            f"SlurmdLogFile={state}/slurmd.log",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core_Memory",
            "DefMemPerCPU=2000",
            "AccountingStorageType=accounting_storage/none",
            "JobAcctGatherType=jobacct_gather/none",
            "JobCompType=jobcomp/none",
            "MinJobAge=300",
            "MpiDefault=none",
            "ReturnToService=2",
            f"NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count()} RealMemory=8000 State=UNKNOWN",
            "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP",
            "",
        ]
    )


def stop(pid_file: Path) -> None:
    if pid_file.is_file():
        try:
            os.kill(int(pid_file.read_text().split()[0]), 15)
        except (ProcessLookupError, ValueError):
            pass


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    missing = [b for b in BINARIES if shutil.which(b) is None and not Path(f"/usr/sbin/{b}").exists()]
    if missing:
        pytest.skip(f"Slurm is not installed (missing {missing}): bash scripts/setup.sh --tests installs it")
    if os.geteuid() != 0:
        pytest.skip("starting munged and slurmd needs root")
    if SLURM_CONF.exists():
        pytest.skip(f"{SLURM_CONF} exists: a Slurm is configured here; not touching it")
    state = tmp_path_factory.mktemp("slurm")
    (state / "state").mkdir()
    (state / "spool").mkdir()
    for folder in ("/run/munge", "/var/log/munge", "/var/lib/munge"):
        Path(folder).mkdir(parents=True, exist_ok=True)
        shutil.chown(folder, "munge", "munge")
    munge_pid = Path("/run/munge/munged.pid")
    subprocess.run(["su", "-s", "/bin/sh", "munge", "-c", "/usr/sbin/munged"], check=True, timeout=30)
    SLURM_CONF.parent.mkdir(parents=True, exist_ok=True)
    SLURM_CONF.write_text(slurm_conf(state))
    pids = [munge_pid, state / "slurmctld.pid", state / "slurmd.pid"]
    try:
        subprocess.run(["/usr/sbin/slurmctld"], check=True, timeout=30)
        subprocess.run(["/usr/sbin/slurmd"], check=True, timeout=30)
        for _ in range(60):
            idle = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True).stdout
            if "idle" in idle:
                break
            time.sleep(1)
        else:  # Slurm is installed and started: a node that never comes up is a failure, not a machine we lack
            logs = "".join(
                (state / f).read_text()[-800:] for f in ("slurmctld.log", "slurmd.log") if (state / f).exists()
            )
            pytest.fail(f"Slurm started but its node did not become idle in 60 s: {logs}")
        yield state
    finally:
        for pid_file in reversed(pids):
            stop(pid_file)
        SLURM_CONF.unlink(missing_ok=True)


@pytest.mark.slow
def test_the_dag_runs_on_slurm_through_the_profile(slurm, tmp_path):
    workdir = tmp_path / "run"
    (workdir / "config").mkdir(parents=True)
    config = tiny_config()
    config["descriptors"] = config["descriptors"][:1]  # a PVHK: no time-scale jobs
    config["library_sizes"] = [4]
    (workdir / "config" / "config.yaml").write_text(yaml.safe_dump(config))
    result = subprocess.run(
        [
            str(SNAKEMAKE),
            "-s",
            str(SNAKEFILE),
            "results/evaluation/predictions.parquet",  # the DAG up to its predictions: each level waits for a check
            "--directory",
            str(workdir),
            "--workflow-profile",
            str(ROOT / "profiles" / "slurm"),
            "--slurm-no-account",  # no accounting here
            # the first status check a second after a submission, not the profile's 5 (the checks then back off by
            # 10 s while nothing finishes): this DAG's 5 levels of 10-second jobs each wait for one
            "--slurm-init-seconds-before-status-checks",
            "1",
            "--group-components",  # the profile's job groups, sized to this 2-core node: two one-core jobs each
            "views=2",
            "descriptors=2",
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert result.returncode == 0, (result.stdout + result.stderr)[-4000:]
    submitted = (result.stdout + result.stderr).count("has been submitted with SLURM jobid")
    # every job the predictions need, the per-object ones in the profile's job groups: one group of the 2 render
    # jobs, one of the 2 describe jobs, then collect, classify and evaluate (the embedded catalogue needs no job)
    assert submitted == 5
    predictions, _ = read_table(workdir / "results" / "evaluation" / "predictions.parquet")
    assert predictions["correct"].mean() > 0.8
