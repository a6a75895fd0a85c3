"""Validation: runs against published experiments and the source study (dam break after Martin & Moyce
1952, granular column collapse after Lube et al. 2005, the source's inclined flow and DP-Cross calibration,
the landslide case)."""
