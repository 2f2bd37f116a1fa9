NOTEBOOK = "02_sign_correction"
FILENAME = "02_sign_correction (1).ipynb"
DESCRIPTION = "the notebook is handed in as '02_sign_correction (1).ipynb', as a browser download names it"
SOLUTIONS = {}
LOSES = set()
