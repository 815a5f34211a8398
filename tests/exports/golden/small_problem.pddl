(define (problem small)
  (:domain wecook)
  (:objects
    p1 p2 - agent
    knife spoon whisk - tool
    chopping_board pot bowl_2 - container
    tomato onion - ingredient
  )
  (:init
    (free p1)
    (free p2)
    (loose knife)
    (loose spoon)
    (loose whisk)
    (loose chopping_board)
    (loose pot)
    (loose bowl_2)
    (loose tomato)
    (loose onion)
    (in tomato chopping_board)
    (in onion bowl_2)
  )
  (:goal (and
    (done-cut tomato)
    (done-transfer tomato)
    (received p2 spoon)
    (done-stir pot)
    (steadied pot)
    (done-transfer onion)
    (done-stir onion)
    (done-stir tomato)
    (in tomato pot)
    (in onion pot)
    (free p1)
    (free p2)
  ))
)
