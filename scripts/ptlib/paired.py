"""Paired alternating runs on a shared, noisy machine: every round runs each
variant once, in the given order in even rounds and reversed in odd ones, so
that load which comes and goes falls on all of them alike; a variant is then
judged by the median of its paired ratios to a baseline (each round's
measurement divided by the baseline's in the same round), with their range.
"""
import statistics


def round_order(variants, round_index):
    """The variants in the order round `round_index` (from 0) runs them."""
    variants = list(variants)
    return variants if round_index % 2 == 0 else variants[::-1]


def run_rounds(rounds, variants, measure, report=None):
    """Runs `measure(variant, round_index)` for every variant in every round, in
    alternating order; returns {variant: [measurement per round]}. `report(variant,
    round_index, value)`, when given, is called after each run."""
    samples = {v: [] for v in variants}
    for r in range(rounds):
        for v in round_order(variants, r):
            value = measure(v, r)
            samples[v].append(value)
            if report:
                report(v, r, value)
    return samples


def paired_ratios(values, baseline):
    """values[i] / baseline[i] for every round both have."""
    return [v / b for v, b in zip(values, baseline)]


class Summary:
    """Median and range of a list of numbers."""

    def __init__(self, values):
        values = list(values)
        if not values:
            raise ValueError("no values")
        self.median, self.low, self.high, self.count = statistics.median(values), min(values), max(values), len(values)

    def __str__(self):
        return f"{self.median:.3f} ({self.low:.3f}-{self.high:.3f})"


def ratio_summary(values, baseline):
    """Summary of the paired ratios values / baseline."""
    return Summary(paired_ratios(values, baseline))
