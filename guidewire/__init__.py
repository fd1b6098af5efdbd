"""The bar-chain guidewire model of Li et al. (Appl. Sci. 2019, 9, 280) on top of :mod:`sqp`."""
