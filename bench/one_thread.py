"""Imported first by the benches that read CPU time (``time.process_time``), before numpy.

``time.process_time`` counts every thread of the process, and after a numpy BLAS call OpenBLAS's
worker threads spin for a while: their CPU was counted as the engine's (the rigid paper scene's
30 s run read 0.065 s against 0.034 s with one BLAS thread, session 20). The engine steps on one
thread; the benches give numpy one too.
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
