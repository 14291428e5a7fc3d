"""Compiling the simulation kernels ahead (:mod:`idkit.studies.compile_ahead`)."""

import os
import subprocess
import sys

from idkit.models import library
from idkit.studies.compile_ahead import compile_kernels


def test_kernels_compiled_in_a_child_are_loaded_not_compiled_by_the_caller(tmp_path):
    """A child compiles the SDOF Maxwell time kernel for a stand-in; the caller then simulates
    another Maxwell system (other order and parameters, the other input path) and compiles
    no driver: it loads the child's from numba's cache. A fresh process with an empty cache."""
    code = (
        "from numba.core import event\n"
        "import numpy as np\n"
        "from idkit.forked import fork_call\n"
        "from idkit.models import library, SDOFSystem, GeneralizedMaxwell\n"
        "from idkit.simulate import simulate\n"
        "from idkit.studies.compile_ahead import compile_kernels\n"
        "call = fork_call(compile_kernels, time=[library.get('system_b1_medium')])\n"
        "print(call.forked, call.result())\n"
        "compiled = []\n"
        "class Listener(event.Listener):\n"
        "    def on_start(self, e): compiled.append(e.data['dispatcher'].py_func.__name__)\n"
        "    def on_end(self, e): pass\n"
        "event.register('numba:compile', Listener())\n"
        "other = SDOFSystem(3.0, GeneralizedMaxwell(k0=2e4, k=[5e3], rate=[80.0]))\n"
        "run = simulate(other, np.arange(11) * 1e-3, base_acceleration=np.ones((2, 11)), workers=1)\n"
        "print(bool(run.ok.all()), 'run_time_batch' in compiled)\n"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), IDKIT_WORKERS="1")
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    lines = result.stdout.strip().splitlines()
    assert lines[-2] == "True ('time: SDOF Maxwell',)"
    assert lines[-1] == "True False"


def test_each_kernel_runs_once_per_structure():
    """Systems of one structure share a kernel; the drop rig and the period map are one kernel each."""
    rope, other_rope = library.get("system_a1_asymmetric"), library.get("system_a1_symmetric")
    hybrid = library.get("hybrid_asymmetric")
    assert compile_kernels(time=[rope, other_rope, hybrid], harmonic=[rope], drop_rig=[rope, hybrid],
                           period_map=[hybrid, rope]) == (
        "time: SDOF Iwan", "time: hybrid Maxwell over Iwan", "harmonic: SDOF Iwan", "drop rig", "period map")
