"""simulate_batch runs the single call's code for every parameter set: the same results."""

import numpy as np

import stickslip

PARAMS = [dict(model="stick-slip", ffk=f, damping=b) for f in (0, 15, 45, 90) for b in (0, 504)]
PARAMS += [dict(model="signum", ffk=45, integrator="euler"),
           dict(model="smooth", ffk=45, smoothing="rational", integrator="symplectic",
                scalar="fixed"),
           dict(model="stick-slip", ffk=45, scalar="float"),
           dict(model="stick-slip", ffk=45, scalar="fixed32", input_range=32.768,
                displacement_range=0.1)]


def without_timing(stats):
    return {k: v for k, v in stats.items() if k != "ns_per_sample"}


def test_batch_equals_single_calls_in_order(lorry_csv):
    recording = stickslip.read_recording(lorry_csv)
    results = stickslip.simulate_batch(recording["a_u"], recording["dt"], PARAMS, threads=2)
    assert len(results) == len(PARAMS)
    for params, (trace, stats) in zip(PARAMS, results):
        single_trace, single_stats = stickslip.simulate(recording["a_u"], recording["dt"],
                                                        **params)
        assert without_timing(stats) == without_timing(single_stats)
        for name in single_trace:
            assert np.array_equal(trace[name], single_trace[name]), (params, name)


def test_thread_count_does_not_change_results(lorry_csv):
    recording = stickslip.read_recording(lorry_csv)
    one = stickslip.simulate_batch(recording["a_u"], recording["dt"], PARAMS, threads=1,
                                   trace=False)
    all_cores = stickslip.simulate_batch(recording["a_u"], recording["dt"], PARAMS, threads=0,
                                         trace=False)
    assert [without_timing(s) for _, s in one] == [without_timing(s) for _, s in all_cores]
    assert all(trace is None for trace, _ in one)


def test_batch_of_a_recording_file_names_it(lorry_csv):
    results = stickslip.simulate_batch(str(lorry_csv), None, [dict(ffk=45)])
    assert results[0][1]["input"] == str(lorry_csv)


def test_empty_batch_gives_an_empty_list():
    assert stickslip.simulate_batch(np.zeros(4), 0.001, []) == []
