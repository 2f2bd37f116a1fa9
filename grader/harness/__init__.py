"""The wire between the grading process and a student's kernel.

The grader writes fixture inputs (``fixtures``); code sent into the kernel
(``kernel_side``) calls the student's functions on them and writes the raw
outputs; the grader reads them back as plain arrays (``outputs``). Expected
values never cross this wire.
"""
