"""How much of what a student's kernel prints the grader keeps: one place for every output cap.

The executor keeps outputs as they arrive within a character budget
(``grader.pipeline.execute``); what a TA is shown is cut again, as notebook
JSON, by ``grader.pipeline.neutralize`` (a submitted notebook carries outputs the
executor never saw). The byte budgets are twice the character budgets: JSON
escaping may double a text's size, never more for what the executor kept.
"""

#: outputs kept per cell and per notebook
MAX_OUTPUTS_PER_CELL = 100
MAX_OUTPUTS_PER_NOTEBOOK = 1000
#: characters of text kept per output
MAX_OUTPUT_CHARS = 20_000
#: characters of output data kept per cell and per notebook while executing
MAX_CELL_OUTPUT_CHARS = 1_000_000
MAX_NOTEBOOK_OUTPUT_CHARS = 8_000_000
#: bytes of notebook JSON kept per cell and per notebook of what a TA opens
MAX_CELL_OUTPUT_BYTES = 2 * 2**20
MAX_NOTEBOOK_OUTPUT_BYTES = 16 * 2**20
