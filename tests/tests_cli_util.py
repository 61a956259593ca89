import subprocess
import sys


def run_zuml(*args: str, timeout: float = 60) -> tuple[int, str, str]:
    """Run the real command line in a child process, as a user would."""
    proc = subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", *args], capture_output=True,
                          text=True, timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr
