"""What a simulation method can do on a case of the failure map (:func:`vibroimpact.benchmarks.workprecision.failure_map`),
in the order the tables and the figure list them; on the standard library alone, so that what reads the map
(its table, its figure) loads none of the methods that make it."""

OUTCOMES = ("correct", "wrong time", "missed impact", "spurious impact", "wrong sequence", "stalled", "crashed")
