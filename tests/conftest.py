"""Test-suite settings. In CI (environment variable CI set) hypothesis draws its examples
from a fixed seed, so a submission's result does not depend on the draw; locally each run
explores new examples (and keeps failing ones in .hypothesis/)."""
import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
