// The notebooks' sliders on the site, without a kernel: each control steps through the
// pictures docs/make_slider_frames.py drew with the notebook's own function, one control at a
// time, the others at their first setting (docs/conf.py writes the controls and the pictures'
// names into the page).
"use strict";

document.addEventListener("DOMContentLoaded", () => {
  for (const block of document.querySelectorAll(".raykit-sliders")) {
    const data = JSON.parse(block.querySelector("script.raykit-sliders-data").textContent);
    const picture = block.querySelector("img");
    const inputs = [...block.querySelectorAll("[data-control]")];
    const show = (moved) => {
      for (const [k, input] of inputs.entries()) {
        const control = data.controls[k];
        if (input !== moved) input.value = String(control.first);
        const stop = Number(input.value);
        const readout = block.querySelector(`output[data-for="${input.id}"]`);
        if (readout) readout.textContent = control.labels[stop];
        if (input === moved) picture.src = data.folder + control.frames[stop];
      }
    };
    for (const input of inputs) input.addEventListener("input", () => show(input));
  }
});
