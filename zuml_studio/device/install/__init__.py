"""Through the ISP programmer (avrdude): ``avrdude`` (one run of it, watched), ``avr_install`` (the ZUML
firmware onto an iMAX B6 and the original back) and ``isp_store`` (the macro store of a B6 whose serial
port only sends).

May import: ``device.errors``, ``device.zuml``, and what ``device`` may."""
