# awk -F, -v column=NAME -v final=N -f rows_one_behind.awk BEFORE.csv AFTER.csv
# Passes (exit 0) if every row of AFTER.csv from the second data row on has
# in COLUMN the value BEFORE.csv has one row earlier, and AFTER's last row
# holds FINAL: a run that makes the same decisions one step later.
FNR == 1 {
  for (i = 1; i <= NF; ++i)
    if ($i == column)
      c = i
  next
}
FILENAME == ARGV[1] {
  before[FNR] = $c
  next
}
{
  after[FNR] = $c
  last = FNR
}
END {
  bad = 0
  for (k = 3; k <= last; ++k)
    if (after[k] != before[k - 1])
      ++bad
  print "rows whose " column " differs from the other run's row before: " bad ", last " after[last] " (" final ")"
  exit (bad > 0 || after[last] != final)
}
