"""How a request runs, whatever it computes (it imports no module of the domain): the
stage cache on disk and the checks of what it reads back (:mod:`.stage_cache`,
:mod:`.entry_reading`), the budget (:mod:`.budget`), progress on stderr (:mod:`.progress`),
result folders written whole or not at all (:mod:`.result_folders`), stops and signals
(:mod:`.interrupts`; the command line's handlers, which name its flags, are ``cli.stops``),
the pools that run any callable on local processes (:mod:`.pools`), where the libraries
keep their own files (:mod:`.library_folders`), the code's identity (:mod:`.provenance`)
and the errors a user can act on (:mod:`.request_errors`).
"""
