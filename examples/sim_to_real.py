"""What does the simulation get wrong on measured loops? Name it, fit it, measure the gain.

Uses the six real plant windows shipped with the package (Xue et al. 2025, Apache-2.0):
``compare`` ranks the effects that tell simulated loops from measured ones, the domain
AUC sums the gap up in one number, and ``calibrate`` fits the catalog's parameters to
the measured loops so that ``make_loops(realism=...)`` simulates loops recorded like them.
Six windows are few: on your own exports, point ``read_loops`` at a folder instead.

Run: python examples/sim_to_real.py [figure.png]
"""

import sys

from sktiction.datasets import load_plant_examples, make_loops
from sktiction.realism import calibrate, compare, plot_compare

measured = load_plant_examples()
n_samples = measured.X.shape[1]

simulated, _ = make_loops(200, n_samples, random_state=0)
table = compare(simulated, measured)
print(table[["effect", "statistic", "simulated", "measured", "effect_size", "significant"]]
      .head(8).to_string(index=False))
print(f"\ndomain AUC, default world: {table.attrs['domain_auc']:.2f}")

realism = calibrate(measured, random_state=0)
print("calibrated make_loops arguments:", realism.overrides)
recorded, _ = make_loops(200, n_samples, realism=realism, random_state=0)
after = compare(recorded, measured)
print(f"domain AUC, calibrated world: {after.attrs['domain_auc']:.2f} "
      f"({after['significant'].sum()} significant effects, before {table['significant'].sum()})")

if len(sys.argv) > 1:
    plot_compare(table, simulated, measured).savefig(sys.argv[1], dpi=100)
    print("figure:", sys.argv[1])
