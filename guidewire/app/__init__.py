"""What a user runs: the command line (:mod:`.cli`, ``python -m guidewire``), figures (:mod:`.plot`,
:mod:`.plot_insertion`, need matplotlib), shape files (:mod:`.export`) and the paper's reproduction
(:mod:`.reproduction`)."""
