"""The workflow's steps and the thesis's experiments: tables in, tables out, called by ``workflow/scripts``.

Each module is one experiment (or one stage of the default run); none draws.
"""
