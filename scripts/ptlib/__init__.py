"""The scripts' shared toolkit (scripts/README.md lists who uses what):

  images   PFM, EXR and PNG images as numpy arrays, top row first
  paired   paired alternating runs: the order of each round, paired ratios, medians
  host     the record every measurement carries: CPU, cores, levels, date, commit
  results  results files (results/): a measurement with its host record and command,
           bench_trace's cells read from Google Benchmark JSON or from a results file
  blocks   generated blocks of a Markdown page (<!-- NAME:begin --> ... <!-- NAME:end -->)

A script imports it after putting scripts/ on its path:
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[N]))  # N: its depth below scripts/
"""
