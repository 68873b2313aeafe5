"""The presenters: one module per format, each turning the records of a request
(``chain.Analysis``, ``stability.StabilityTable``, ``envelope.Envelope``,
``sweeps.VerdictGrid``, a study's dataset) into what a user reads. No record imports a
presenter; a command is parse -> compute -> present.

- :mod:`.text`: what a command prints;
- :mod:`.summary`: the JSON objects of ``summary.json``;
- :mod:`.tables`: the CSV files;
- :mod:`.figures`: the PNG figures (drawn in the plot process);
- :mod:`.files`: ``pressure.vtu`` and ``squeal.wav``;
- :mod:`.html`: ``report.html``.
"""
