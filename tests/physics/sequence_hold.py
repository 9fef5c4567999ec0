"""physics.sequence_hold: the globals of sequence.prm (a quasistatic preload,
then Verlet). The step numbers run on (0-4 the load steps, then every second
Verlet step to 44); while the load is held (1 <= t < 2) the kinetic energy
stays at round-off (the load goes in the step that ends at t = 2): the explicit solver started from the preload's
equilibrium, u and f (from u = 0 the strain energy, 6.4e-5, would go into
motion); after the load goes (t = 2) the bar swings."""
import csv
import sys

rows = list(csv.DictReader(open("output/sequence.globals.csv")))
steps = [int(r["step"]) for r in rows]
expected = [0, 1, 2, 3, 4] + list(range(6, 45, 2))
hold = [float(r["kinetic_energy"]) for r in rows if 1 <= float(r["time"]) < 1.99]
moving = [float(r["kinetic_energy"]) for r in rows if float(r["time"]) > 2.5]
strain = float(rows[4]["strain_energy"])
print("steps:", " ".join(map(str, steps)))
print("strain energy after the preload: %.6e" % strain)
print("largest kinetic energy while held: %.3e (limit 1e-20)" % max(hold))
print("largest kinetic energy after the release: %.3e (at least 1e-6)" % max(moving))
ok = steps == expected and max(hold) < 1e-20 and max(moving) > 1e-6 and abs(strain - 6.4367e-5) < 1e-8
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
