"""The modules of hertzgear report (scripts/hertzgear_report.py):

    artifacts  reading a run directory (CSV tables, JSON, used_parameters.prm, the Fourier
               coefficients of stiffness.json, scene quantities, the load and design map with
               its contact-grid cells) and writing files atomically
    signals    time-series analysis for the dynamics figures
    plotting   matplotlib style and the drawing helpers the figures share
    figures    one function per figure
    html       the page: sections, tables, key results
    report     which figures and tables each section of the page gets
"""
